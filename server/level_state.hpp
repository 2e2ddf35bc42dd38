// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The level the stream plays at (docs/loudness.md): --level auto or physical, the target loudness, and
// what was chosen for the scene playing. The scene manager writes it (a scene load's choice, /loudness);
// the queries read it (/loudness). The listening gain is the scene's (SceneDescription::gain_db, /gain).
//
// Thread: the control thread only.

#include <cmath>
#include <memory>
#include <string>

#include "engine/render/level_choice.hpp"
#include "engine/render/output_stage.hpp"

namespace ameoto {

struct LevelState {
    bool automatic = true;                  // --level auto
    double target_lufs = default_target_lufs;
    double measured_lufs = -HUGE_VAL;       // the scene's default rain, integrated, at the physical scale
    double level_gain_db = 0.0;             // chosen for the scene playing (0 with --level physical)
    std::shared_ptr<const LevelRecording> recording;   // what the choice measured: /loudness finds another
                                            // target's gain from it (through the limiter, on the worker)
    bool limiter = false;
    double full_scale_pa = 100.0;           // the engine's full scale (RendererConfig::full_scale_pa)

    // The choice made for the scene now playing (the first scene, a load).
    void adopt(const LevelChoice& c) {
        measured_lufs = c.measured_lufs;
        level_gain_db = c.gain_db;
        recording = c.recording;
    }
    // What that choice measured, for another target's gain (retarget_level).
    LevelChoice measured() const {
        LevelChoice c;
        c.measured_lufs = measured_lufs;
        c.gain_db = level_gain_db;
        c.recording = recording;
        return c;
    }
};

// "level auto: scene 'pond' (default rain 1.5 mm/h) measures -104.1 LUFS at the physical scale; level gain
// +81.1 dB; 0 dBFS = 52.9 dB SPL": the log line of a load, and the WAV's comment (with the gain).
std::string describe_level(const LevelState& level, const std::string& scene, double default_rain_mm_per_h, double gain_db);

}  // namespace ameoto
