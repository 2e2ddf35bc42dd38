// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench engine`: every method of bench_methods.hpp on canopy panels of the sizes asked for,
// then on the mi-faust triangle mesh beside Faust itself (bench_faust.hpp). docs/bench.md.
//
// Interface:
//   int status = run_engine_bench(options, io);   // measurements on io.out, progress on io.err
//   double d = max_relative_difference(ours, reference);   // max |a - b| / max |b|
//
// Output: text (a table per mesh, the Faust comparison, then the two targets: at most half of Faust's
// time per sample, 10 000 masses in real time) or, with --json, one JSON object per line per
// measurement (bench_report.hpp), nothing else on stdout. The process is pinned to the CPU it started
// on for the whole benchmark (Faust's program, a child, inherits it; the mask is restored at the
// end); Faust is timed before and after ameoto's rows on its mesh and the two medians averaged.
// Panels: a force of 1 N for one sample at a node near the panel's centre every 0.1 s (rain-like
// impulses), the net force summed. Triangle mesh: the .dsp's pluck and output (bench_drive.hpp).
// Before timing the triangle mesh, each method renders check_samples samples from rest; their
// largest difference to Faust's, relative to Faust's peak, is `faust_difference` (the same model
// gives rounding-level differences for the explicit Verlet rows; the other integrators are other
// schemes and differ by their own discretisation error).

#include <vector>

#include "clients/ameoto/bench_options.hpp"
#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

constexpr long check_samples = 4800;   // 0.1 s at 48 kHz: the pluck and its ringing

double max_relative_difference(const std::vector<double>& ours, const std::vector<double>& reference);
int run_engine_bench(const BenchOptions& options, const CommandIo& io);

}  // namespace ameoto::client
