// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench accuracy`: speed against accuracy for every integration method on the umbrella panel,
// the stability map, and the data the accuracy knob chooses from (engine/core/method_choice.hpp).
//
// Interface:
//   int status = run_accuracy_bench(words, io);   // words: everything after "ameoto bench"
//   AccuracyRow r = measure_method(mesh, setting, reference, seconds, runs);
//   std::string usage = accuracy_bench_usage();
//
// Rows: explicit Verlet at 1x, 2x, 4x and 8x sub-steps (1x runs what stability needs), symplectic
// Euler, trapezoidal, backward Euler, modal with 8, 16, 32 and all audible modes, on the default
// umbrella's panel (bench_mesh.hpp, 50 masses, nylon, 48 kHz). Cost: ns per output sample (thread CPU
// time, median of runs, bench_timer.hpp) as the scene uses a panel under heavy rain: the template
// tier's force on one node every sample, the step, and the far field's read of every node's velocity
// (the modal scheme forms each from its modes: O(modes) per node), and % of one core at 48 kHz for that
// panel (the default umbrella has 8); also the quiet figure, the step alone with 1 N every 0.1 s (bench
// engine's drive), and the contact figure: every node's displacement read as well, as the collider's
// broad phase does while a lattice drop is near. Errors: bench_accuracy_errors.hpp.
// Then the canopy in air (bench_accuracy_air.hpp), held to the FDTD reference's committed figures (or
// recomputed with --air-reference DX): the reference's cost, the air-loaded modal canopy, and every
// method above in vacuum, by the worst cents of the struck panel's first 10 modes (CSV rows "canopy in air").
// Then the free drop (bench_accuracy_drop.hpp): explicit Verlet and symplectic Euler at 1x..8x the
// sub-steps it needs, frequency error of its n = 2 oscillation and cost (CSV rows "free drop").
// Then the scene's drop tiers (bench_accuracy_tiers.hpp): full, template, texture: CPU per drop, and the
// long-term spectrum against the full tier's for the same rain (CSV rows "drop tiers", cost in ns_per_drop).
// Outputs: a text table (or --json, one object per row), --csv FILE, --svg FILE (cost against error,
// the Pareto front; a third panel for the canopy in air, a fourth for the tiers), --stability-svg FILE (the stability map) and --table FILE (the C++ source of
// engine/core/method_table.cpp, the knob's data). docs/accuracy.md has the command that regenerates
// everything committed.

#include <string>

#include "clients/ameoto/bench_accuracy_errors.hpp"
#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

struct AccuracyRow {
    std::string body;
    MeasuredMethod method;
    MethodErrors errors;
    double ns_quiet = 0.0;     // ns per sample, the step alone with 1 N every 0.1 s (bench engine's drive)
    double ns_contact = 0.0;   // ns per sample with every node's displacement read (a lattice drop near)
    bool front_cents = false, front_decibels = false;
    double core_percent() const { return method.ns_per_sample * 48000.0 * 1e-9 * 100.0; }
};

AccuracyRow measure_method(const BenchMesh& mesh, const MethodSetting& setting, const AccuracyReference& reference,
                           double seconds, int runs);
std::string accuracy_bench_usage();
int run_accuracy_bench(const CommandWords& words, const CommandIo& io);

}  // namespace ameoto::client
