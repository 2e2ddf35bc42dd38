// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_command.hpp"

#include <algorithm>

#include "clients/ameoto/bench_accuracy.hpp"
#include "clients/ameoto/bench_drop.hpp"
#include "clients/ameoto/bench_engine.hpp"
#include "clients/ameoto/bench_formats.hpp"
#include "clients/ameoto/bench_lattices.hpp"
#include "clients/ameoto/bench_levels.hpp"
#include "clients/ameoto/bench_options.hpp"
#include "clients/ameoto/bench_scene.hpp"
#include "clients/ameoto/exit_status.hpp"

namespace ameoto::client {

std::string bench_usage() {
    return "usage: ameoto bench engine [--json] [--seconds S] [--sizes N,N,...] [--runs R] [--no-faust]\n"
           "       ameoto bench drop [--json] [--runs R]\n"
           "       ameoto bench scene [--json] [--seconds S]\n"
           "       ameoto bench formats [--json] [--seconds S]\n"
           "       ameoto bench accuracy [--json] [--csv FILE] [--svg FILE] [--stability-svg FILE] [--table FILE]\n"
           "       ameoto bench lattices [--max-diameter MM] [--table FILE]\n"
           "       ameoto bench levels [--seconds S] [--scene NAME]... [--json | --markdown]\n"
           "\n"
           "drop: the cost of the seed's full model, 5 mm water drops at terminal speed on the 8-panel\n"
           "nylon canopy at 48 kHz (impact and breakup), and how many at once one core can carry.\n"
           "scene: the drops per second one core holds at each level of detail (full, template,\n"
           "texture), and heavy rain (50 mm/h, umbrella and pond) in 64-frame blocks: mean and\n"
           "99.9th percentile callback time (--seconds x 4 s of audio per measurement, 1..20).\n"
           "formats: heavy rain (50 mm/h, umbrella and pond) at 48 kHz in 256-frame blocks as stereo and\n"
           "as ambix:1, 2, 3: ns per sample, % of a core and the ratio to stereo, in the same run\n"
           "(--seconds x 4 s of audio per format and round, 3 rounds; docs/output-formats.md).\n"
           "accuracy: cost against error of every integration method on the umbrella panel, the\n"
           "stability map, and the accuracy knob's data (ameoto bench accuracy --help; docs/accuracy.md).\n"
           "lattices: the drop lattices' stretch-mode analysis, timed per lattice, and its committed table\n"
           "(ameoto bench lattices --help; engine/models/stretch_mode_table.hpp).\n"
           "levels: each built-in scene's LAeq and Leq at its listener at its default rain, 25, 50 and\n"
           "100 mm/h, and the slope per decade of rain rate (ameoto bench levels --help; docs/levels.md).\n"
           "\n"
           "Measures the physics engine on this machine (no server needed): every method (the\n"
           "transverse network with each integrator, the grid membrane in float and double) on\n"
           "umbrella panels of the given sizes, then on Faust's mi-faust triangleMesh.dsp beside\n"
           "Faust's own code when faust is installed (scripts/install-bench-deps), with the ratio.\n"
           "Prints ns per sample, per mass update and per link update, % of one core and the\n"
           "realtime factor at 48 kHz. Progress goes to stderr.\n"
           "\n"
           "Options (each suite takes only those in its usage line above; another is refused):\n"
           "  --json              one JSON object per measurement, one per line (fields: docs/bench.md)\n"
           "  --seconds S         CPU time spent measuring each method at each size, 0.01..600\n"
           "                      (default 0.5; a tenth warms up, the rest is split into the runs)\n"
           "  --sizes N,N,...     panel sizes in masses, 1..200000 each (default 55,1000,10000)\n"
           "  --runs R            timed runs per measurement, 1..101; the median is reported (default 5);\n"
           "                      drop: rounds of its three scenes back to back, the least and the median\n"
           "  --no-faust          skip the comparison with Faust\n"
           "\n"
           "Exit status: 0 measured; 2 usage error.\n"
           "\n"
           "Examples:\n"
           "  ameoto bench engine\n"
           "  ameoto bench engine --sizes 10000 --seconds 2\n"
           "  ameoto bench engine --json | jq 'select(.mesh == \"canopy panel\") | .realtime_factor'\n";
}

int run_bench(const CommandWords& words, const CommandIo& io) {
    if (std::find(words.begin(), words.end(), "accuracy") != words.end()) return run_accuracy_bench(words, io);
    if (std::find(words.begin(), words.end(), "lattices") != words.end()) return run_lattices_bench(words, io);
    if (std::find(words.begin(), words.end(), "levels") != words.end()) return run_levels_bench(words, io);
    BenchOptions options;
    std::string error;
    switch (parse_bench_options(words, options, error)) {
        case BenchParse::help: io.out << bench_usage(); return exit_status::ok;
        case BenchParse::error: io.err << "ameoto bench: " << error << "\n(see ameoto bench --help)\n"; return exit_status::usage;
        case BenchParse::run: break;
    }
    if (options.suite == "drop") return run_drop_bench(options, io);
    if (options.suite == "scene") return run_scene_bench(options, io);
    if (options.suite == "formats") return run_formats_bench(options, io);
    return run_engine_bench(options, io);
}

}  // namespace ameoto::client
