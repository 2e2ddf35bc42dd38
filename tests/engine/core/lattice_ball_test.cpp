// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/lattice_ball: the FCC lattice drop (seed Fig. 8, one mass per 1 mm drop volume).
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "engine/core/lattice_ball.hpp"

using ameoto::Vec3;

namespace {

std::vector<int> links_per_mass(const ameoto::Body3D& body) {
    std::vector<int> count(static_cast<std::size_t>(body.mass_count()), 0);
    for (int l = 0; l < body.link_count(); ++l) {
        ++count[static_cast<std::size_t>(body.link_a(l))];
        ++count[static_cast<std::size_t>(body.link_b(l))];
    }
    return count;
}

}  // namespace

TEST_CASE("lattice_ball: the seed's mass count, D^3 for D in mm") {
    CHECK(ameoto::seed_mass_count(5e-3) == 125);
    CHECK(ameoto::seed_mass_count(1e-3) == 1);
    CHECK(ameoto::seed_mass_count(0.5e-3) == 1);   // at least one mass
    CHECK(ameoto::seed_mass_count(2.5e-3) == 16);
}

TEST_CASE("lattice_ball: counts near D^3, exact mass, 12 neighbours inside, centre of mass on the centre") {
    const Vec3 centre{0.01, -0.02, 0.5};
    for (double d_mm : {1.0, 2.0, 3.0, 5.0, 8.0}) {
        CAPTURE(d_mm);
        const double d = d_mm * 1e-3;
        ameoto::LatticeBallSpec spec;
        spec.diameter = d;
        spec.centre = centre;
        spec.stiffness = 10.0;
        const auto ball = ameoto::make_lattice_ball(spec);
        const auto& body = ball.body;
        const auto& info = ball.info;
        const double target = d_mm * d_mm * d_mm;
        MESSAGE("D = " << d_mm << " mm: " << info.mass_count << " masses (target " << target << "), "
                        << info.link_count << " links, spacing " << info.spacing * 1e3 << " mm, offset "
                        << info.sphere_offset * 1e3 << " mm");
        REQUIRE(body.mass_count() == info.mass_count);
        REQUIRE(body.link_count() == info.link_count);
        if (d_mm == 1.0) {
            CHECK(info.mass_count == 1);
            CHECK(info.link_count == 0);
            CHECK(info.spacing == ameoto::test::relative(d));
        } else {
            CHECK(std::abs(info.mass_count - target) <= 0.2 * target);
        }

        // Mass: rho pi D^3 / 6, shared equally, conserved to rounding.
        const double total = ameoto::constants::water_density * ameoto::constants::pi * d * d * d / 6.0;
        CHECK(info.total_mass == ameoto::test::relative(total).epsilon(1e-15));
        CHECK(body.total_mass() == ameoto::test::relative(total).epsilon(1e-14));
        for (int i = 0; i < body.mass_count(); ++i) CHECK(body.mass(i) == info.node_mass);

        // Centre of mass on the requested centre (rounding of |centre| = 0.5 m: 1e-15 m is 1e-12 of D).
        CHECK(ameoto::norm(body.centre_of_mass() - centre) < 1e-12);

        // Links: each joins two masses exactly one spacing apart (its rest length), once.
        std::set<std::pair<int, int>> seen;
        for (int l = 0; l < body.link_count(); ++l) {
            const int a = std::min(body.link_a(l), body.link_b(l)), b = std::max(body.link_a(l), body.link_b(l));
            CHECK(seen.insert({a, b}).second);
            CHECK(body.rest_length(l) == info.spacing);
            CHECK(ameoto::norm(body.position(a) - body.position(b)) == ameoto::test::relative(info.spacing).epsilon(1e-9));
            CHECK(body.link_kind(l) == ameoto::LinkKind::spring);
        }
        // Neighbours: at most 12, and exactly 12 for every mass whose 12 lattice neighbours (all within
        // one spacing) lie inside the cutting sphere; no two masses closer than one spacing.
        const auto count = links_per_mass(body);
        int interior = 0;
        for (int i = 0; i < body.mass_count(); ++i) {
            CHECK(count[static_cast<std::size_t>(i)] <= 12);
            const double r = ameoto::norm(body.position(i) - centre);
            CHECK(r <= d / 2 + info.sphere_offset + 1e-12);   // inside the sphere it was cut from
            if (r + info.sphere_offset + info.spacing < d / 2) {
                ++interior;
                CHECK(count[static_cast<std::size_t>(i)] == 12);
            }
            for (int j = 0; j < i; ++j)
                CHECK(ameoto::norm(body.position(i) - body.position(j)) > info.spacing * (1.0 - 1e-9));
        }
        if (d_mm >= 5.0) CHECK(interior > 0);
        // The lattice fills the sphere: count * (volume per site h^3 / sqrt 2) within 25 % of the volume.
        const double filled = info.mass_count * std::pow(info.spacing, 3) / std::sqrt(2.0);
        if (d_mm > 1.0) CHECK(filled == ameoto::test::relative(ameoto::constants::pi * d * d * d / 6.0).epsilon(0.25));
    }
}

TEST_CASE("lattice_ball: the 5 mm drop of the seed") {
    const auto ball = ameoto::make_lattice_ball({.diameter = 5e-3});
    // 122 masses (a triangle-centred cut; 125 is not a shell count of FCC), 3 fewer than the seed's 125.
    CHECK(ball.info.mass_count == doctest::Approx(125).epsilon(0.05));
    // About 6 links per mass (12 neighbours, each link shared), fewer at the surface.
    CHECK(ball.info.link_count > 4 * ball.info.mass_count);
    CHECK(ball.info.link_count < 6 * ball.info.mass_count);
}

TEST_CASE("lattice_ball: a target count overrides the seed's rule; balls append to a body") {
    ameoto::Body3D body;
    const int before = body.add_mass(1.0, Vec3{1.0, 0.0, 0.0});
    ameoto::LatticeBallSpec spec;
    spec.diameter = 3e-3;
    spec.target_masses = 400;
    spec.link_kind = ameoto::LinkKind::breakable;
    spec.stiffness = 5.0;
    spec.damping = 1e-6;
    spec.break_force = 0.01;
    const auto info = ameoto::add_lattice_ball(body, spec);
    CHECK(before == 0);
    CHECK(info.first_mass == 1);
    CHECK(info.first_link == 0);
    CHECK(body.mass_count() == 1 + info.mass_count);
    CHECK(std::abs(info.mass_count - 400) <= 40);
    for (int l = 0; l < body.link_count(); ++l) {
        CHECK(body.link_kind(l) == ameoto::LinkKind::breakable);
        CHECK(body.link_a(l) >= 1);
        CHECK(body.link_b(l) >= 1);
    }
    // A second ball goes after the first.
    const auto second = ameoto::add_lattice_ball(body, {.diameter = 2e-3, .centre = Vec3{0.0, 0.0, 0.1}});
    CHECK(second.first_mass == 1 + info.mass_count);
    CHECK(second.first_link == info.link_count);
}

TEST_CASE("lattice_ball: bad input is refused") {
    CHECK_THROWS_AS(ameoto::make_lattice_ball({.diameter = 0.0}), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::make_lattice_ball({.diameter = -1e-3}), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::make_lattice_ball({.diameter = 1e-3, .density = 0.0}), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::make_lattice_ball({.diameter = 1e-3, .target_masses = 1000000}), std::invalid_argument);
}

TEST_CASE("lattice_ball: the batch choice for many targets equals the per-target one; shapes scale to balls") {
    const auto choices = ameoto::lattice_ball_choices(160);
    REQUIRE(choices.size() == 160);
    for (int t = 1; t <= 160; ++t) {
        CAPTURE(t);
        const auto& c = choices[static_cast<std::size_t>(t - 1)];
        const auto shape = ameoto::lattice_ball_shape(t);
        CHECK(shape.centre_kind == c.centre_kind);
        CHECK(shape.last_shell_key == c.last_key);
        CHECK(shape.mass_count() == c.count);
    }
    // A shape from a choice is the one add_lattice_ball places: positions times D about the centre.
    ameoto::LatticeBallSpec spec;
    spec.diameter = 3e-3;
    spec.centre = Vec3{0.1, 0.2, 0.3};
    const auto ball = ameoto::make_lattice_ball(spec);
    const auto shape = ameoto::lattice_ball_shape(choices[26]);   // target 27
    REQUIRE(shape.mass_count() == ball.info.mass_count);
    REQUIRE(shape.link_count() == ball.info.link_count);
    for (int i = 0; i < shape.mass_count(); ++i)
        CHECK(ameoto::norm(ball.body.position(i) - (spec.centre + spec.diameter * shape.position[static_cast<std::size_t>(i)])) == 0.0);
    for (int l = 0; l < shape.link_count(); ++l) {
        CHECK(ball.body.link_a(l) == shape.link_a[static_cast<std::size_t>(l)]);
        CHECK(ball.body.link_b(l) == shape.link_b[static_cast<std::size_t>(l)]);
    }
    CHECK(ball.info.spacing == spec.diameter * shape.spacing);
}
