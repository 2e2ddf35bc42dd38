// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The n = 2 stretch mode of every drop lattice up to the protocol's largest drop, computed once and
// committed (engine/models/stretch_mode_table.cpp), so that start-up does not run stretch_mode()
// (drop.hpp: a sparse LDL^T and 30 solves per lattice, about half of ameotod's start-up CPU).
//
// Interface:
//   std::span<const TabulatedStretchMode> t = tabulated_stretch_modes();   // stretch_mode_table.cpp
//   const char* how = tabulated_stretch_modes_source();                     // the command that wrote it
//   std::optional<StretchMode> m = tabulated_stretch_mode(shape);           // drop.hpp: the lookup
//
// Identity: a lattice ball's shape is fixed by its centre kind and the key of its last shell
// (lattice_ball.hpp: "two shapes with equal kind and key are the same"); the entry also holds the
// shape's mass and link counts, and the lookup takes an entry only when all four agree, so a change
// to the ball's construction that alters the counts falls back to computing. Values are stretch_mode()'s
// results written as hexadecimal floating literals (exact: the table gives the same bits as the
// computation, so renders do not change). tests/engine/models/stretch_mode_table_test.cpp recomputes
// every entry and compares exactly, so the table cannot go stale silently.
//
// Regenerate (after any change to stretch_mode() or lattice_ball.*), then rebuild:
//   build/bin/ameoto bench lattices --table engine/models/stretch_mode_table.cpp
// (clients/ameoto/bench_lattices.cpp; --max-diameter MM, default 8: the protocol's largest /drop).

#include <cstdint>
#include <span>

namespace ameoto {

struct TabulatedStretchMode {
    int centre_kind = 0;             // LatticeBallShape::centre_kind
    long long last_shell_key = 0;    // LatticeBallShape::last_shell_key
    int masses = 0, links = 0;       // the shape's counts (checked by the lookup)
    double lambda = 0.0, weight = 0.0;   // StretchMode: lambda_2 for k = m = 1, its share of the stretch
};

std::span<const TabulatedStretchMode> tabulated_stretch_modes();   // stretch_mode_table.cpp
const char* tabulated_stretch_modes_source();

}  // namespace ameoto
