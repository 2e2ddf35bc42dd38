// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench drop`: what the seed's full model costs: one 5 mm water drop at terminal speed on the
// 8-panel nylon canopy at 48 kHz (lattice drop, breakup, collisions, far-field sound), and how many
// such drops one core could carry at once.
//
// Interface:
//   int status = run_drop_bench(options, io);   // prints a table, or one JSON object per line (--json)
//
// Measurements (thread CPU time, each over the same 0.1 s of audio; --runs rounds, each timing the three
// scenes back to back; each scene's least run and its median run are reported):
//   canopy        the scene with no drop: canopy, collider, far field (the baseline)
//   1 drop        one 5 mm drop, timed over the first 0.1 s after it is placed (impact and breakup:
//                 the expensive part; afterwards most pieces are in the air and cheap)
//   8 drops       eight 5 mm drops placed at once on different panels, same window
// Per drop: (time with drops - baseline) / drops. Drops at once in real time: (period - baseline) /
// per drop, with period = 1 / 48000 s. The target is 16, judged on the least runs: work that
// does the same every run can only be lengthened by what else the machine does (Chen & Revels, "Robust
// benchmarking in noisy environments", 2016), and this shared VM's speed moves by half within seconds
// (docs/bench.md). The figure from the medians and each round's own figure are printed beside it.

#include "clients/ameoto/bench_options.hpp"
#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

int run_drop_bench(const BenchOptions& options, const CommandIo& io);

}  // namespace ameoto::client
