// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto render drop --diameter MM [...] -o FILE.wav [--plot FILE.svg]`: renders one lattice drop
// falling on the umbrella offline (engine/models/drop_on_canopy.hpp) to a 32-bit float WAV, with an
// optional SVG of its breakup and sound (svg_plot.hpp); needs no server. docs/cli-offline.md, "ameoto render drop".
//
// Interface:
//   int status = run_render(words, io);   // words: everything after "ameoto render"
//   std::cout << render_usage();          // ameoto render --help, ameoto help render
//   RenderDropOptions o; std::string error;
//   RenderParse p = parse_render_drop_options(words, o, error);   // words after "ameoto render drop"
//
// Output: one summary line on stdout (duration, pieces at the end, peak level); on a terminal a
// progress indication on stderr unless --quiet. Exit: 0 rendered; 1 the render failed (the file
// could not be written, the engine refused the configuration); 2 usage error.

#include <cstdint>
#include <optional>
#include <string>

#include "clients/ameoto/command_io.hpp"
#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/wet_impact.hpp"
#include "engine/scene/output_format.hpp"

namespace ameoto::client {

struct RenderDropOptions {
    double diameter_mm = 0.0;           // required, 0.1..8
    double speed_m_per_s = 0.0;         // 0: terminal speed; else 0.1..30
    std::string material = "nylon";
    std::string liquid = "water";
    double seconds = 1.0;               // 0.01..60
    int rate = 48000;                   // Hz, 8000..192000
    std::uint64_t seed = 1;             // picks the impact point when --x/--y are not given
    std::optional<double> x, y;         // m, canopy coordinates; both or neither
    SceneOutput output = SceneOutput::far_field;
    int channels = 1;                   // 1 or 2 (--channels), or the format's (--format)
    std::optional<OutputFormat> format; // --format: ring:1 (mono), ears (the default for 2), stereo, ring:N, ambix:N
    int coarse_steps = 4;               // 1..64: samples a splash in the air may take as one (1: never)
    ImpactModel impact = ImpactModel::wet;   // --impact wet|seed (engine/models/wet_impact.hpp)
    bool air = true;                    // --air on|off: the canopy's modes in air heard as dipoles
                                        // (engine/models/air_canopy.hpp), or the lattice in vacuum, baffled
    bool quiet = false;
    std::string wav_path;               // -o, required
    std::string plot_path;              // --plot, optional
};

enum class RenderParse { run, help, error };

RenderParse parse_render_drop_options(const CommandWords& words, RenderDropOptions& options, std::string& error);

int run_render(const CommandWords& words, const CommandIo& io);
std::string render_usage();

}  // namespace ameoto::client
