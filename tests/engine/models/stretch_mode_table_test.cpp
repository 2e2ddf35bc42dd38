// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/stretch_mode_table (the committed stretch modes) and its lookup in drop.cpp:
// every entry recomputed with stretch_mode() to the bit, every shape up to 8 mm covered, and the
// fallback to computing for a shape the table lacks.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <utility>

#include "engine/core/lattice_ball.hpp"
#include "engine/models/drop.hpp"
#include "engine/models/stretch_mode_table.hpp"

namespace {

using ShapeKey = std::pair<int, long long>;   // centre kind, last shell key: a shape's identity

// Every distinct shape chosen for some target 1..max_target, by identity.
std::map<ShapeKey, ameoto::LatticeBallChoice> shapes_up_to(int max_target) {
    std::map<ShapeKey, ameoto::LatticeBallChoice> shapes;
    for (const auto& c : ameoto::lattice_ball_choices(max_target)) shapes.emplace(ShapeKey{c.centre_kind, c.last_key}, c);
    return shapes;
}

}  // namespace

// Exact, not approximate: the table must give the bits the computation gives (the audio is compared
// bit for bit). Both run the same code on the same inputs with no fast-math, so a difference means the
// table is stale: regenerate it (stretch_mode_table.hpp has the command).
TEST_CASE("stretch mode table: every entry equals stretch_mode() recomputed, bit for bit") {
    const auto table = ameoto::tabulated_stretch_modes();
    REQUIRE(!table.empty());
    int largest = 0;
    for (const auto& t : table) largest = std::max(largest, t.masses);
    // A shape of n masses is chosen for the target n itself at the latest (its own count is nearest).
    const auto shapes = shapes_up_to(largest);
    std::map<ShapeKey, int> seen;
    for (const auto& t : table) {
        CAPTURE(t.centre_kind);
        CAPTURE(t.last_shell_key);
        CAPTURE(t.masses);
        CHECK(++seen[ShapeKey{t.centre_kind, t.last_shell_key}] == 1);   // each shape once
        const auto it = shapes.find(ShapeKey{t.centre_kind, t.last_shell_key});
        REQUIRE(it != shapes.end());   // an entry no target picks: a stale table
        const ameoto::LatticeBallShape shape = ameoto::lattice_ball_shape(it->second);
        CHECK(shape.mass_count() == t.masses);
        CHECK(shape.link_count() == t.links);
        const ameoto::StretchMode computed = ameoto::stretch_mode(shape);
        CHECK(computed.lambda == t.lambda);
        CHECK(computed.weight == t.weight);
    }
}

TEST_CASE("stretch mode table: every drop up to 8 mm is tabulated, and drop_lattice uses the table") {
    const int max_target = ameoto::seed_mass_count(8e-3);   // the protocol's largest /drop: 512 masses
    const auto shapes = shapes_up_to(max_target);
    for (const auto& [key, choice] : shapes) {
        CAPTURE(key.first);
        CAPTURE(key.second);
        const ameoto::LatticeBallShape shape = ameoto::lattice_ball_shape(choice);
        const auto tabulated = ameoto::tabulated_stretch_mode(shape);
        REQUIRE(tabulated.has_value());
        const auto lattice = ameoto::drop_lattice(choice.count);
        REQUIRE(lattice->shape.last_shell_key == key.second);
        CHECK(lattice->lambda2 == tabulated->lambda);
        CHECK(lattice->weight2 == tabulated->weight);
    }
    const auto table = ameoto::drop_lattices(max_target);
    for (int t = 1; t <= max_target; ++t) CHECK(ameoto::tabulated_stretch_mode(table[static_cast<std::size_t>(t - 1)]->shape).has_value());
}

TEST_CASE("stretch mode table: a shape it does not hold is computed (the fallback)") {
    // Beyond the table's largest drop: the first shape above its largest entry.
    int largest = 0;
    for (const auto& t : ameoto::tabulated_stretch_modes()) largest = std::max(largest, t.masses);
    int target = largest + 1;
    while (ameoto::lattice_ball_shape(target).mass_count() <= largest) ++target;
    const ameoto::LatticeBallShape shape = ameoto::lattice_ball_shape(target);
    CAPTURE(shape.mass_count());
    CHECK(!ameoto::tabulated_stretch_mode(shape).has_value());
    const ameoto::StretchMode computed = ameoto::stretch_mode(shape);
    CHECK(computed.lambda > 0.0);
    CHECK(computed.weight > 0.5);
    const auto lattice = ameoto::drop_lattice(target);
    CHECK(lattice->mass_count() == shape.mass_count());
    CHECK(lattice->lambda2 == computed.lambda);
    CHECK(lattice->weight2 == computed.weight);

    // A tabulated identity whose counts disagree (the ball's construction changed) is not taken.
    ameoto::LatticeBallShape altered = ameoto::lattice_ball_shape(125);
    REQUIRE(ameoto::tabulated_stretch_mode(altered).has_value());
    altered.link_a.pop_back();
    altered.link_b.pop_back();
    CHECK(!ameoto::tabulated_stretch_mode(altered).has_value());
}
