// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench formats`: what each output format costs: heavy rain (50 mm/h on the umbrella and a
// 4 x 3 m pond 3 m away, as bench scene's) rendered at 48 kHz in 256-frame blocks as stereo and as
// Ambisonics of order 1, 2 and 3, with the level of detail fixed (every format renders the same drops),
// thread CPU time per sample, and each format's ratio to stereo and extra share of a core, measured
// in the same run (the formats in turn, three rounds, the least of each).
//
// Interface:
//   int status = run_formats_bench(options, io);   // a table, or one JSON object per format (--json)

#include "clients/ameoto/bench_options.hpp"
#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

int run_formats_bench(const BenchOptions& options, const CommandIo& io);

}  // namespace ameoto::client
