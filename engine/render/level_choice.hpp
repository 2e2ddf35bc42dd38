// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --level auto: the level gain that makes a scene's default rain play at a target loudness.
//
// Interface (off the audio thread: it builds a renderer and renders; about a second of CPU for the umbrella):
//   LevelChoice c = choose_level(config, target_lufs);   // config: configure_for_scene's, at the scene's own rain
//   config.level_gain_db = c.gain_db;
//   auto parts = Renderer::make_parts(config);                 // or: one build of the umbrella for both the
//   LevelChoice c = choose_level(config, *parts, target_lufs); // measurement and the stream, which then
//   Renderer stream(config_at_its_rain, parts.get());          // builds nothing more
//   LevelChoice d = retarget_level(c, other_target_lufs);      // another target, from c's recorded samples
//
// How: the scene is rendered offline for `seconds` at its default rain with the same engine and seed as the
// stream (fixed detail, the physical samples: level gain, gain and limiter off), its integrated loudness
// measured (loudness.hpp), and gain = target - measured. With config.limiter (as ameotod and render scene
// run --level auto) the gain is then found through the limiter the stream plays through: raised until the
// recorded samples, limited, measure the target (a peaky programme loses loudness to the limiter's hold on
// its peaks), by at most max_limiter_share_db. Chosen once per scene load, never again while it
// plays: it is not an automatic gain control, so heavier rain stays louder by the physical amount (the slope
// of level against rain rate is the physical one; tests/engine/render/level_choice_test.cpp).
// A scene whose default rain is silent (rate 0, or nothing to strike) gets 0 dB: the physical level.
// A node (config.node, ameotod --node K) measures the whole scene, not its own part: every node of a
// scene then plays with one gain, and their outputs still sum to the whole scene's.

#include <memory>
#include <vector>

#include "engine/render/renderer.hpp"

namespace ameoto {

// The samples a choice measured (the physical scale), kept so another target is found from them.
struct LevelRecording {
    std::vector<float> interleaved;
    int channels = 2;
    double sample_rate = 48000.0;
    bool limiter = false;         // the stream plays through the limiter: find the gain through it
};

struct LevelChoice {
    double measured_lufs = 0.0;   // the default rain's integrated loudness at the physical scale (-inf: silent)
    double gain_db = 0.0;         // the level gain chosen, within [min_level_gain_db, max_level_gain_db]
    double seconds = 0.0;         // rendered
    double limiter_db = 0.0;      // of gain_db, what makes up for the limiter (0: limiter off, or not needed)
    double played_lufs = 0.0;     // the recorded samples' loudness at gain_db, through the limiter if on
    std::shared_ptr<const LevelRecording> recording;   // null for a silent scene
};

inline constexpr double default_target_lufs = -23.0;   // EBU R 128's programme loudness
inline constexpr double min_target_lufs = -60.0, max_target_lufs = -5.0;
inline constexpr double min_level_gain_db = -60.0, max_level_gain_db = 120.0;
inline constexpr double level_choice_seconds = 3.0;
inline constexpr double max_limiter_share_db = 12.0;   // the most gain --level auto gives to make up for the limiter

LevelChoice choose_level(const RendererConfig& config, double target_lufs, double seconds = level_choice_seconds);
// The same from the umbrella's parts (Renderer::make_parts; they must fit config): the same choice.
LevelChoice choose_level(const RendererConfig& config, const UmbrellaParts& parts, double target_lufs,
                         double seconds = level_choice_seconds);
// The choice for another target from the samples `measured` recorded (no render; through the limiter a few
// passes over them, tens of milliseconds: call it off the control thread, as /loudness does).
LevelChoice retarget_level(const LevelChoice& measured, double target_lufs);

}  // namespace ameoto
