// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/canopy: the umbrella's panels, where a point lands, and the runtime guard.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/core/random.hpp"
#include "engine/models/canopy.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

namespace {

const ameoto::Canopy& default_canopy() {
    static const ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    return canopy;
}

}  // namespace

TEST_CASE("canopy: plan area is N R^2 sin(2 pi / N) / 2") {
    for (int n : {3, 6, 8, 12}) {
        for (double r : {0.3, 0.5, 0.7}) {
            CAPTURE(n);
            CAPTURE(r);
            const ameoto::Canopy c(ameoto::CanopyGeometry{n, r, 30}, ameoto::MembraneMaterial::nylon_canopy(), kT);
            // canopy.hpp: plan area (rounding only).
            CHECK(c.area() == ameoto::test::relative(n * r * r * std::sin(2.0 * kPi / n) / 2.0).epsilon(1e-12));
            CHECK(c.panel_count() == n);
        }
    }
    // canopy.hpp: 0.707 m^2 for 8 panels of 0.5 m.
    CHECK(default_canopy().area() == ameoto::test::relative(0.7071).epsilon(1e-3));
}

TEST_CASE("canopy: default panels have about 50 masses and are stable") {
    const auto& c = default_canopy();
    REQUIRE(c.panel_count() == 8);
    for (int k = 0; k < c.panel_count(); ++k) {
        const int masses = c.panel(k).network.mass_count();
        // Seed (physics.md s.1): umbrella panel of about 50 masses; brief: 40..60.
        CHECK(masses >= 40);
        CHECK(masses <= 60);
        CHECK(c.panel(k).network.stability().margin() < 0.9);
    }
    // Hem free, ribs fixed: some nodes anchored, and the hem row is not.
    const auto& lat = c.panel(0).lattice;
    int anchored = 0;
    for (int a : lat.anchor_links) anchored += a > 0;
    CHECK(anchored > 0);
    CHECK(anchored < static_cast<int>(lat.nodes.size()));
}

TEST_CASE("canopy: locate finds the panel under a point") {
    const auto& c = default_canopy();
    for (int k = 0; k < c.panel_count(); ++k) {
        CAPTURE(k);
        const auto p = c.panel_centroid(k);
        const auto hit = c.locate(p.x, p.y);
        CHECK(hit.panel == k);
        CHECK(hit.node >= 0);
        CHECK(hit.node < c.panel(k).network.mass_count());
        // The centroid lies along the panel's azimuth at 2/3 of its height from the shaft.
        CHECK(std::atan2(p.y, p.x) == doctest::Approx(std::remainder(c.panel_azimuth(k), 2.0 * kPi)).epsilon(1e-12));
        CHECK(std::hypot(p.x, p.y) == ameoto::test::relative(2.0 / 3.0 * 0.5 * std::cos(kPi / 8)).epsilon(1e-12));
    }
    // Outside the radius at any azimuth: no panel.
    for (int i = 0; i < 360; ++i) {
        const double a = 2.0 * kPi * i / 360.0;
        CHECK(c.locate(0.501 * std::cos(a), 0.501 * std::sin(a)).panel == -1);
        CHECK(c.locate(2.0 * std::cos(a), 2.0 * std::sin(a)).panel == -1);
    }
    // Between the hem chord and the circle, on a panel's centre line: not on the (flat) canopy.
    CHECK(c.locate(0.48, 0.0).panel == -1);
    CHECK(c.locate(0.45, 0.0).panel == 0);
}

TEST_CASE("canopy: locate returns the node nearest the point, in the panel's frame") {
    // Rotating a point by one sector maps it onto the same node of the next panel (identical panels).
    const auto& c = default_canopy();
    ameoto::Random rng(8);
    for (int t = 0; t < 200; ++t) {
        const auto p = c.sample_point(rng);
        const auto hit = c.locate(p.x, p.y);
        REQUIRE(hit.panel >= 0);
        const double s = 2.0 * kPi / c.panel_count();
        const auto moved = c.locate(p.x * std::cos(s) - p.y * std::sin(s), p.x * std::sin(s) + p.y * std::cos(s));
        CHECK(moved.panel == (hit.panel + 1) % c.panel_count());
        CHECK(moved.node == hit.node);
    }
}

TEST_CASE("canopy: sample_point is uniform over the canopy") {
    const auto& c = default_canopy();
    ameoto::Random rng(11);
    const int n = 10000;
    std::vector<int> per_panel(static_cast<std::size_t>(c.panel_count()), 0);
    int off = 0, inner = 0;
    for (int i = 0; i < n; ++i) {
        const auto p = c.sample_point(rng);
        const auto hit = c.locate(p.x, p.y);
        if (hit.panel < 0) {
            ++off;
            continue;
        }
        ++per_panel[static_cast<std::size_t>(hit.panel)];
        // Uniform over a triangle from the shaft: P(distance < half the apothem) = 1/4.
        const double along = std::hypot(p.x, p.y) * std::cos(std::remainder(std::atan2(p.y, p.x), 2.0 * kPi / 8));
        inner += along < 0.5 * 0.5 * std::cos(kPi / 8);
    }
    CHECK(off == 0);   // every sample lands on the canopy
    const double mean = static_cast<double>(n) / c.panel_count();
    double chi2 = 0.0;
    for (int k : per_panel) {
        // Brief: each panel within 10 % of the mean (the binomial sd is 2.6 % of it, so ~4 sigma).
        CHECK(static_cast<double>(k) == doctest::Approx(mean).epsilon(0.10));
        chi2 += (k - mean) * (k - mean) / mean;
    }
    // Chi-square with 7 degrees of freedom: the 0.1 % critical value is 24.3.
    CHECK(chi2 < 24.3);
    // Binomial sd sqrt(n p (1-p)) = 43 around 2500; 5 sigma.
    CHECK(std::abs(inner - 0.25 * n) < 5.0 * std::sqrt(n * 0.25 * 0.75));
}

TEST_CASE("canopy: forces move the hit panel only, and the runtime guard resets a non-finite panel") {
    ameoto::Canopy c(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    std::vector<double> forces(static_cast<std::size_t>(c.panel_count()));
    const auto p = c.panel_centroid(3);
    const auto hit = c.locate(p.x, p.y);
    c.apply_force(hit, 0.5);
    c.step(forces.data());
    for (int k = 0; k < c.panel_count(); ++k) {
        CAPTURE(k);
        if (k == 3) CHECK(forces[static_cast<std::size_t>(k)] == ameoto::test::relative(0.5).epsilon(1e-12));   // first step: the external force
        else CHECK(forces[static_cast<std::size_t>(k)] == 0.0);
    }
    c.apply_force({}, 1.0);   // panel -1: ignored
    c.step(forces.data());
    CHECK(c.reset_unstable() == 0);

    // A non-finite force makes panel 3 non-finite; the guard resets exactly that panel.
    c.apply_force(hit, std::numeric_limits<double>::infinity());
    c.step(forces.data());
    c.step(forces.data());
    CHECK_FALSE(c.panel_finite(3));
    CHECK(c.panel_finite(2));
    CHECK(c.reset_unstable() == 1);
    CHECK(c.panel_finite(3));
    CHECK(c.reset_unstable() == 0);
    c.step(forces.data());
    for (double f : forces) CHECK(std::isfinite(f));
}

TEST_CASE("canopy: rejects bad geometry") {
    const auto mat = ameoto::MembraneMaterial::nylon_canopy();
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{2, 0.5, 50}, mat, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{65, 0.5, 50}, mat, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{8, 0.0, 50}, mat, kT), std::invalid_argument);
}

TEST_CASE("canopy: flat by default; nodes carry 3-D rest positions and normals") {
    const auto& c = default_canopy();
    CHECK(c.flat());
    CHECK(c.nodes_per_panel() == c.panel(0).network.mass_count());
    for (int k = 0; k < c.panel_count(); ++k) {
        for (int i = 0; i < c.nodes_per_panel(); ++i) {
            const auto p = c.rest_position(k, i), n = c.normal(k, i);
            CHECK(p.z == 0.0);
            CHECK(n.x == 0.0);
            CHECK(n.y == 0.0);
            CHECK(n.z == 1.0);
            // The node's plan point is where locate() finds that node (canopy.hpp: plan lattice).
            const auto hit = c.locate(p.x, p.y);
            CHECK(hit.panel == k);
            CHECK(hit.node == i);
        }
    }
}

TEST_CASE("canopy: curvature puts the nodes on a spherical cap, moving along its normal") {
    const double rc = 1.2, r = 0.5;
    ameoto::Canopy curved(ameoto::CanopyGeometry{8, r, 50, rc}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    const auto& flat = default_canopy();
    CHECK_FALSE(curved.flat());
    REQUIRE(curved.nodes_per_panel() == flat.nodes_per_panel());
    const ameoto::Vec3 centre{0.0, 0.0, -rc};   // canopy.hpp: z = 0 at the shaft's top
    for (int k = 0; k < curved.panel_count(); ++k) {
        for (int i = 0; i < curved.nodes_per_panel(); ++i) {
            const auto p = curved.rest_position(k, i), n = curved.normal(k, i), q = flat.rest_position(k, i);
            // Same plan point as the flat canopy, lifted onto the sphere |p - centre| = Rc (rounding).
            CHECK(p.x == doctest::Approx(q.x).epsilon(1e-15));
            CHECK(p.y == doctest::Approx(q.y).epsilon(1e-15));
            CHECK(ameoto::norm(p - centre) == ameoto::test::relative(rc).epsilon(1e-14));
            // Unit normal along the radius, pointing out and up.
            CHECK(ameoto::norm(n) == ameoto::test::relative(1.0).epsilon(1e-14));
            const auto radial = (p - centre) / rc;
            CHECK(ameoto::norm(n - radial) < 1e-14);
            CHECK(n.z > 0.0);
            CHECK(curved.rest_height(p.x, p.y) == p.z);
        }
    }
    // Rim height sqrt(Rc^2 - R^2) - Rc (a 0.109 m deep cap for Rc = 1.2 m), shaft at 0.
    CHECK(curved.rest_height(r, 0.0) == ameoto::test::relative(std::sqrt(rc * rc - r * r) - rc).epsilon(1e-14));
    CHECK(curved.rest_height(0.0, 0.0) == 0.0);
    // A force moves the node along its normal: position = rest + u n.
    std::vector<double> forces(8);
    const auto hit = curved.locate(0.3, 0.1);
    REQUIRE(hit.panel >= 0);
    curved.apply_force(hit, 1.0);
    curved.step(forces.data());
    const double u = curved.displacement(hit.panel, hit.node);
    CHECK(u > 0.0);
    const auto moved = curved.node_position(hit.panel, hit.node) - curved.rest_position(hit.panel, hit.node);
    CHECK(ameoto::norm(moved - u * curved.normal(hit.panel, hit.node)) < 1e-16);   // rounding of |rest| ~ 0.3 m
    CHECK(curved.normal_velocity(hit.panel, hit.node) == ameoto::test::relative(u / kT).epsilon(1e-12));   // from rest
    // The dynamics are the flat panel's (shallow shell, canopy.hpp): the same net force.
    ameoto::Canopy flat2(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    std::vector<double> flat_forces(8);
    flat2.apply_force(hit, 1.0);
    flat2.step(flat_forces.data());
    CHECK(flat_forces == forces);
}

TEST_CASE("canopy: geometry and materials are checked, with reasons; stability policies apply") {
    const auto nylon = ameoto::MembraneMaterial::nylon_canopy();
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{8, 0.5, 50, 0.5}, nylon, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{8, 0.5, 50, 0.3}, nylon, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{8, 0.5, 0}, nylon, kT), std::invalid_argument);
    const auto geometry = ameoto::Canopy::check(ameoto::CanopyGeometry{8, 0.5, 50, 0.4}, nylon, kT);
    CHECK_FALSE(geometry.ok);
    CHECK(geometry.reason.find("radius of curvature") != std::string::npos);

    // An invalid material is refused with its reason (membrane.hpp ranges).
    const auto bad = ameoto::MembraneMaterial::custom("mud", 0.06, -5.0, 20.0, 2e-6);
    const auto verdict = ameoto::Canopy::check(ameoto::CanopyGeometry{}, bad, kT);
    CHECK_FALSE(verdict.ok);
    CHECK(verdict.reason.find("tension -5 N/m is outside") != std::string::npos);
    try {
        ameoto::Canopy c(ameoto::CanopyGeometry{}, bad, kT);
        FAIL("an invalid material must be refused");
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()) == verdict.reason);
    }

    // The seed's nylon: sub-steps by default (27 at 48 kHz, docs/integrators.md), refused under 'refuse'.
    const auto seed = ameoto::MembraneMaterial::seed_nylon();
    const ameoto::Canopy sub(ameoto::CanopyGeometry{}, seed, kT);
    CHECK(sub.panel(0).network.stability().sub_steps == 27);
    ameoto::NetworkOptions refuse;
    refuse.stability.policy = ameoto::StabilityPolicy::refuse;
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{}, seed, kT, refuse), ameoto::StabilityError);
    const auto refused = ameoto::Canopy::check(ameoto::CanopyGeometry{}, seed, kT, refuse);
    CHECK_FALSE(refused.ok);
    CHECK(refused.reason.find("omega_max T = 51") != std::string::npos);
    CHECK(ameoto::Canopy::check(ameoto::CanopyGeometry{}, seed, kT).stability.sub_steps == 27);
}

namespace {

// Canopy::locate as it was first written, kept as the reference: the panel by atan2, the rotation by
// std::cos / std::sin of its azimuth, polygon_contains on the outline, the brute-force nearest node.
ameoto::CanopyHit reference_locate(const ameoto::Canopy& c, double x, double y) {
    const int n = c.panel_count();
    const double sector = 2.0 * ameoto::constants::pi / n;
    int panel = static_cast<int>(std::lround(std::atan2(y, x) / sector));
    panel = ((panel % n) + n) % n;
    const double half_angle = ameoto::constants::pi / n;
    const double w = c.geometry().radius_m * std::sin(half_angle), h = c.geometry().radius_m * std::cos(half_angle);
    const double a = c.panel_azimuth(panel);
    const double along = x * std::cos(a) + y * std::sin(a);
    const double across = -x * std::sin(a) + y * std::cos(a);
    const ameoto::Point2 local{across, h - along};
    const std::vector<ameoto::PolygonEdge> outline = {{{-w, 0.0}, false}, {{w, 0.0}, true}, {{0.0, h}, true}};
    if (!ameoto::polygon_contains(outline, local)) return {};
    return {panel, c.panel(panel).lattice.nearest_node_brute_force(local)};
}

}  // namespace

TEST_CASE("canopy: locate gives exactly the reference formula's hit (atan2, sincos, brute force)") {
    struct Shape {
        int panels;
        double radius;
        int masses;
    };
    // 3 and 5 panels: a sector boundary on the -x axis, where atan2 jumps; 2 m: edges longer than 1 m.
    const Shape shapes[] = {{8, 0.5, 50}, {3, 0.4, 30}, {5, 0.5, 80}, {12, 0.7, 40}, {64, 0.5, 12}, {8, 2.0, 200}};
    ameoto::Random rng(21);
    long queries = 0, on_canopy = 0;
    for (const Shape& shape : shapes) {
        const ameoto::Canopy c(ameoto::CanopyGeometry{shape.panels, shape.radius, shape.masses},
                               ameoto::MembraneMaterial::nylon_canopy(), kT);
        const double r = shape.radius;
        std::vector<ameoto::Point2> points;
        for (int t = 0; t < 20000; ++t) points.push_back({rng.uniform(-1.2 * r, 1.2 * r), rng.uniform(-1.2 * r, 1.2 * r)});
        for (int t = 0; t < 2000; ++t) points.push_back(c.sample_point(rng));
        // On and a few ulps beside the ribs (the sector boundaries), out to the rib tips and beyond.
        for (int k = 0; k <= shape.panels; ++k) {
            const double b = (k - 0.5) * 2.0 * ameoto::constants::pi / shape.panels;
            for (int t = 0; t < 40; ++t) {
                const double d = rng.uniform(0.0, 1.1 * r);
                double x = d * std::cos(b), y = d * std::sin(b);
                points.push_back({x, y});
                for (int step = 0; step < 3; ++step) {
                    x = std::nextafter(x, t % 2 ? 1e300 : -1e300);
                    y = std::nextafter(y, t % 3 ? 1e300 : -1e300);
                    points.push_back({x, y});
                }
                points.push_back({x * (1.0 + 1e-9), y});
                points.push_back({x, y * (1.0 + 1e-9)});
            }
        }
        // The shaft and its signed zeros, the node sites, the hem, NaN and infinities.
        for (const double x : {0.0, -0.0, 1e-300, -1e-300})
            for (const double y : {0.0, -0.0, 1e-300, -1e-300}) points.push_back({x, y});
        for (int k = 0; k < c.panel_count(); ++k)
            for (int i = 0; i < c.nodes_per_panel(); ++i) points.push_back({c.rest_position(k, i).x, c.rest_position(k, i).y});
        for (int t = 0; t < 200; ++t) {
            const double a = rng.uniform(0.0, 2.0 * ameoto::constants::pi), d = r * std::cos(ameoto::constants::pi / shape.panels);
            points.push_back({d * std::cos(a), d * std::sin(a)});
        }
        const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
        for (const ameoto::Point2 p : {ameoto::Point2{nan, 0.1}, {0.1, nan}, {inf, 0.0}, {-inf, 1.0}, {0.0, -inf}, {1e300, 1e300}})
            points.push_back(p);
        for (const ameoto::Point2 p : points) {
            const ameoto::CanopyHit want = reference_locate(c, p.x, p.y), got = c.locate(p.x, p.y);
            if (got.panel != want.panel || got.node != want.node) {
                CAPTURE(shape.panels);
                CAPTURE(p.x);
                CAPTURE(p.y);
                CHECK(got.panel == want.panel);
                CHECK(got.node == want.node);
            }
            ++queries;
            on_canopy += want.panel >= 0 ? 1 : 0;
        }
    }
    MESSAGE(queries, " points (", on_canopy, " on the canopy), every hit identical to the reference");
    CHECK(on_canopy > 50000);
}

TEST_CASE("canopy: displacement_range is the lowest and highest u over every node") {
    ameoto::Canopy c(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    CHECK(c.displacement_range().lowest == 0.0);
    CHECK(c.displacement_range().highest == 0.0);
    std::vector<double> forces(static_cast<std::size_t>(c.panel_count()));
    c.apply_force(c.locate(0.2, 0.03), -0.5);
    c.apply_force(c.locate(-0.1, -0.25), 0.3);
    bool up = false, down = false;
    for (int n = 0; n < 40; ++n) {
        c.step(forces.data());
        double lo = 1e300, hi = -1e300;
        for (int k = 0; k < c.panel_count(); ++k)
            for (int i = 0; i < c.nodes_per_panel(); ++i) {
                lo = std::min(lo, c.displacement(k, i));
                hi = std::max(hi, c.displacement(k, i));
                up = up || c.displacement(k, i) > 0.0;
                down = down || c.displacement(k, i) < 0.0;
            }
        CHECK(c.displacement_range().lowest == lo);
        CHECK(c.displacement_range().highest == hi);
    }
    CHECK(up);
    CHECK(down);
}
