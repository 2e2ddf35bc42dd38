// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench scene`: what rain scenes cost: the drops per second one core can hold at each level of
// detail, and the callback time of heavy rain on the umbrella and a pond in 64-frame blocks.
//
// Interface:
//   int status = run_scene_bench(options, io);   // a table, or one JSON object per line (--json)
//   SceneDescription s = heavy_rain_bench_scene(); // its heavy rain (also `bench formats`'): any thread
//
// Measurements (thread CPU time, the renderer ameotod runs, 48 kHz stereo):
//   tiers       the umbrella scene with every rain drop forced into one tier (full: lattice drops;
//               template; texture), against the same scene without rain: CPU per drop, and the drops
//               per second one core holds = (1 - the dry scene's share of a core) / CPU per drop
//   heavy rain  50 mm/h on the umbrella (0.707 m^2, about 5 000 drops per second) plus a 4 x 3 m pond
//               3 m away, in 64-frame blocks, the governor running on the load it measures as the
//               server's does: mean and 99.9th percentile callback time as % of the block period
//               (issue 5's targets: 25 % and 60 %)

#include "clients/ameoto/bench_options.hpp"
#include "clients/ameoto/command_io.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto::client {

int run_scene_bench(const BenchOptions& options, const CommandIo& io);
SceneDescription heavy_rain_bench_scene();   // the umbrella at 50 mm/h and a 4 x 3 m pond 3 m away

}  // namespace ameoto::client
