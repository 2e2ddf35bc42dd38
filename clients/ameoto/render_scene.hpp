// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto render scene [--scene NAME|FILE.scene] [--rain MM/H] [--seconds S] [--rate HZ] [--seed N]
// [--channels N | --format F] [--level auto|physical] [--loudness LUFS] [--gain DB] [--limiter on|off] [--quiet] -o FILE.wav`: renders a rain scene offline with the renderer the server runs
// (engine/render/renderer.hpp), to a 32-bit float WAV; needs no server. The same scene, seed and rate
// give the same samples as ameotod --offline (the governor ignores machine load offline), through the same
// output stage (engine/render/output_stage.hpp) and level choice (level_choice.hpp). docs/cli-offline.md.
//
// Interface:
//   RenderSceneOptions o; std::string error;
//   RenderParse p = parse_render_scene_options(words, o, error);   // words after "ameoto render scene"
//   int status = run_render_scene(o, io);

#include <cstdint>
#include <optional>
#include <string>

#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/format_option.hpp"
#include "clients/ameoto/render_drop.hpp"
#include "engine/models/wet_impact.hpp"

namespace ameoto::client {

struct RenderSceneOptions {
    std::string scene = "umbrella";     // a built-in name, or a path ending in .scene
    std::optional<double> rain_mm_per_h;   // 0..500; default: the scene's
    double seconds = 10.0;              // 0.01..3600
    int rate = 48000;                   // Hz, 8000..192000
    std::uint64_t seed = 1;
    std::string hrtf = "/usr/share/libmysofa/default.sofa";   // --hrtf FILE.sofa: binaural's HRIRs
    FormatChoice format;                // --format or --channels (1..16); default: the scene's, else stereo
    std::optional<bool> air;            // --air on|off: overrides every umbrella's air= key
    std::optional<ImpactModel> impact;  // --impact wet|seed: overrides every umbrella's impact= key
    bool quiet = false;
    std::string wav_path;               // -o, required
    bool level_auto = true;             // --level auto|physical (docs/loudness.md)
    double target_lufs = -23.0;         // --loudness, -60..-5 LUFS
    std::optional<double> gain_db;      // --gain, -80..80 dB; default: the scene's `output gain=`
    std::optional<bool> limiter;        // --limiter on|off; default: on with level auto
};

RenderParse parse_render_scene_options(const CommandWords& words, RenderSceneOptions& options, std::string& error);
int run_render_scene(const RenderSceneOptions& options, const CommandIo& io);
std::string render_scene_usage();

}  // namespace ameoto::client
