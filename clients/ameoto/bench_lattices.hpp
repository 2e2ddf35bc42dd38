// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench lattices`: the drop lattices' n = 2 stretch-mode analysis (drop.hpp, stretch_mode), timed
// per lattice, and the C++ source of its committed table (engine/models/stretch_mode_table.cpp).
//
// Interface:
//   int status = run_lattices_bench(words, io);   // words: everything after "ameoto bench"
//   auto rows = compute_stretch_modes(max_target); // every distinct shape for targets 1..max_target
//   std::string cpp = stretch_mode_table_source(rows, max_diameter_mm);
//   std::string usage = lattices_bench_usage();
//
// Rows: one per distinct lattice shape (centre kind, last shell key) that a target mass count up to
// round((max diameter / 1 mm)^3) picks (lattice_ball_choices), in order of first use, with
// stretch_mode()'s lambda_2 and weight, and the thread CPU time of that call. The table holds the
// values as hexadecimal floating literals (%a: exact, so the table gives the computation's bits).
// stretch_mode_table.hpp has the command that regenerates it.

#include <string>
#include <vector>

#include "clients/ameoto/command_io.hpp"
#include "engine/models/stretch_mode_table.hpp"

namespace ameoto::client {

struct LatticeRow {
    TabulatedStretchMode mode;
    double cpu_seconds = 0.0;   // stretch_mode() on this shape, thread CPU time
};

std::vector<LatticeRow> compute_stretch_modes(int max_target);
std::string stretch_mode_table_source(const std::vector<LatticeRow>& rows, double max_diameter_mm);
std::string lattices_bench_usage();
int run_lattices_bench(const CommandWords& words, const CommandIo& io);

}  // namespace ameoto::client
