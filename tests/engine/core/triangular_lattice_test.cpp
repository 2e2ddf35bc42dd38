// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/triangular_lattice: the node lattice over a convex polygon with fixed/free edges.
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/core/triangular_lattice.hpp"

using ameoto::Point2;
using ameoto::PolygonEdge;

namespace {

std::vector<PolygonEdge> square(double side, bool fixed_bottom = true, bool fixed_rest = true) {
    return {{{0, 0}, fixed_bottom}, {{side, 0}, fixed_rest}, {{side, side}, fixed_rest}, {{0, side}, fixed_rest}};
}

std::vector<PolygonEdge> triangle(bool fixed) {
    // Not symmetric, not axis-aligned on two sides.
    return {{{0.0, 0.0}, fixed}, {{0.9, 0.1}, fixed}, {{0.3, 0.7}, fixed}};
}

std::vector<PolygonEdge> umbrella_panel() {
    // The canopy's panel outline (models/canopy.cpp): hem free, ribs fixed, 8 panels of 0.5 m.
    const double w = 0.5 * std::sin(3.14159265358979323846 / 8), h = 0.5 * std::cos(3.14159265358979323846 / 8);
    return {{{-w, 0.0}, false}, {{w, 0.0}, true}, {{0.0, h}, true}};
}

std::vector<int> link_counts(const ameoto::TriangularLattice& lat) {
    std::vector<int> c(lat.nodes.size(), 0);
    for (const auto& l : lat.links) {
        ++c[static_cast<std::size_t>(l.a)];
        ++c[static_cast<std::size_t>(l.b)];
    }
    return c;
}

double distance_to_boundary(const std::vector<PolygonEdge>& poly, Point2 p) {
    double best = 1e300;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Point2 a = poly[i].start, b = poly[(i + 1) % poly.size()].start;
        const double ex = b.x - a.x, ey = b.y - a.y;
        best = std::min(best, std::abs(ex * (p.y - a.y) - ey * (p.x - a.x)) / std::hypot(ex, ey));
    }
    return best;
}

}  // namespace

TEST_CASE("triangular_lattice: polygon area and containment") {
    CHECK(ameoto::polygon_area(square(2.0)) == doctest::Approx(4.0).epsilon(1e-15));
    CHECK(ameoto::polygon_area(triangle(true)) == ameoto::test::relative(0.5 * (0.9 * 0.7 - 0.1 * 0.3)).epsilon(1e-15));
    CHECK(ameoto::polygon_contains(square(1.0), {0.5, 0.5}));
    CHECK_FALSE(ameoto::polygon_contains(square(1.0), {1.5, 0.5}));
    CHECK_FALSE(ameoto::polygon_contains(square(1.0), {0.5, -0.01}));
    CHECK_FALSE(ameoto::polygon_contains(triangle(true), {0.8, 0.6}));
}

TEST_CASE("triangular_lattice: construction rejects bad input") {
    CHECK_THROWS_AS(ameoto::build_triangular_lattice({{{0, 0}, true}, {{1, 0}, true}}, 0.1), std::invalid_argument);
    // Clockwise polygon.
    CHECK_THROWS_AS(ameoto::build_triangular_lattice({{{0, 0}, true}, {{0, 1}, true}, {{1, 0}, true}}, 0.1), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::build_triangular_lattice(square(1.0), 0.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::spacing_for_node_count(square(1.0), 0), std::invalid_argument);
}

TEST_CASE("triangular_lattice: node area and link geometry") {
    const double h = 0.037;
    const auto lat = ameoto::build_triangular_lattice(triangle(true), h);
    CHECK(lat.spacing == h);
    // triangular_lattice.hpp: node area (sqrt 3 / 2) h^2 (rounding only).
    CHECK(lat.node_area == ameoto::test::relative(std::sqrt(3.0) / 2.0 * h * h).epsilon(1e-14));
    REQUIRE(lat.anchor_links.size() == lat.nodes.size());
    for (const auto& p : lat.nodes) CHECK(ameoto::polygon_contains(triangle(true), p));
    // Every link joins two distinct nodes one spacing apart (a triangular lattice), and no pair twice.
    std::vector<std::vector<int>> seen(lat.nodes.size());
    for (const auto& l : lat.links) {
        REQUIRE(l.a != l.b);
        const Point2 a = lat.nodes[static_cast<std::size_t>(l.a)], b = lat.nodes[static_cast<std::size_t>(l.b)];
        CHECK(std::hypot(a.x - b.x, a.y - b.y) == ameoto::test::relative(h).epsilon(1e-12));
        for (int other : seen[static_cast<std::size_t>(l.a)]) CHECK(other != l.b);
        seen[static_cast<std::size_t>(l.a)].push_back(l.b);
        seen[static_cast<std::size_t>(l.b)].push_back(l.a);
    }
    // ... and every pair of nodes one spacing apart is linked.
    std::size_t close_pairs = 0;
    for (std::size_t i = 0; i < lat.nodes.size(); ++i)
        for (std::size_t j = i + 1; j < lat.nodes.size(); ++j)
            close_pairs += std::hypot(lat.nodes[i].x - lat.nodes[j].x, lat.nodes[i].y - lat.nodes[j].y) < 1.01 * h;
    CHECK(close_pairs == lat.links.size());
}

TEST_CASE("triangular_lattice: spacing_for_node_count hits its target") {
    for (const auto& poly : {square(0.4), triangle(true), umbrella_panel()}) {
        for (int target : {30, 50, 200}) {
            CAPTURE(target);
            const auto lat = ameoto::build_triangular_lattice(poly, ameoto::spacing_for_node_count(poly, target));
            // Brief: within 15 % of the target (the count is a step function of the spacing).
            CHECK(static_cast<double>(lat.nodes.size()) == doctest::Approx(target).epsilon(0.15));
        }
    }
}

TEST_CASE("triangular_lattice: six neighbours everywhere when all edges are fixed") {
    const auto poly = square(1.0);
    const auto lat = ameoto::build_triangular_lattice(poly, 0.02);   // ~2900 nodes
    REQUIRE(lat.nodes.size() > 2000);
    const auto links = link_counts(lat);
    int interior = 0, boundary = 0;
    for (std::size_t i = 0; i < lat.nodes.size(); ++i) {
        CAPTURE(i);
        // Fixed edges: every missing neighbour is a fixed point, so links + anchors = 6 for all nodes.
        CHECK(links[i] + lat.anchor_links[i] == 6);
        if (distance_to_boundary(poly, lat.nodes[i]) > 1.01 * lat.spacing) {
            ++interior;
            CHECK(links[i] == 6);
            CHECK(lat.anchor_links[i] == 0);
        } else if (links[i] < 6) {
            ++boundary;
            CHECK(lat.anchor_links[i] > 0);   // every boundary node is held
        }
    }
    CHECK(interior > 2000);
    CHECK(boundary > 100);
}

TEST_CASE("triangular_lattice: free edges have no anchors") {
    SUBCASE("all edges free") {
        const auto lat = ameoto::build_triangular_lattice(triangle(false), 0.03);
        int missing = 0;
        const auto links = link_counts(lat);
        for (std::size_t i = 0; i < lat.nodes.size(); ++i) {
            CHECK(lat.anchor_links[i] == 0);
            missing += 6 - links[i];
        }
        CHECK(missing > 0);   // the boundary nodes lack neighbours: a free boundary
    }
    SUBCASE("bottom edge free, others fixed: only nodes near the fixed edges are anchored") {
        const auto poly = square(1.0, false, true);
        const auto lat = ameoto::build_triangular_lattice(poly, 0.05);
        const double row = lat.spacing * std::sqrt(3.0) / 2.0;
        const auto links = link_counts(lat);
        int bottom_row = 0;
        for (std::size_t i = 0; i < lat.nodes.size(); ++i) {
            const Point2 p = lat.nodes[i];
            const bool near_sides = p.x < 1.01 * lat.spacing || p.x > 1.0 - 1.01 * lat.spacing || p.y > 1.0 - 1.01 * row;
            if (p.y < row && !near_sides) {
                ++bottom_row;
                // triangular_lattice.hpp: first row half a row inside; its two lower neighbours lie
                // across the free edge and are simply absent.
                CHECK(p.y == doctest::Approx(row / 2.0).epsilon(1e-12));
                CHECK(lat.anchor_links[i] == 0);
                CHECK(links[i] == 4);
            }
            if (lat.anchor_links[i] > 0) CHECK(near_sides);
        }
        CHECK(bottom_row > 10);
    }
}

TEST_CASE("triangular_lattice: node count times node area approximates the polygon area") {
    const auto poly = triangle(true);
    const auto lat = ameoto::build_triangular_lattice(poly, ameoto::spacing_for_node_count(poly, 200));
    // Brief: within 15 % for a 200-node triangle (boundary cells are cut).
    CHECK(lat.nodes.size() * lat.node_area == ameoto::test::relative(ameoto::polygon_area(poly)).epsilon(0.15));
    // And it converges: a much finer lattice is within 2 % (perimeter * h / area ~ 1.5 %).
    const auto fine = ameoto::build_triangular_lattice(poly, lat.spacing / 8.0);
    CHECK(fine.nodes.size() * fine.node_area == ameoto::test::relative(ameoto::polygon_area(poly)).epsilon(0.02));
}

TEST_CASE("triangular_lattice: nearest_node returns the nearest node") {
    const auto lat = ameoto::build_triangular_lattice(umbrella_panel(), 0.04);
    REQUIRE(lat.nodes.size() > 20);
    for (std::size_t i = 0; i < lat.nodes.size(); ++i) CHECK(lat.nearest_node(lat.nodes[i]) == static_cast<int>(i));
    ameoto::Random rng(3);
    for (int t = 0; t < 2000; ++t) {
        const Point2 p{rng.uniform(-0.3, 0.3), rng.uniform(-0.1, 0.6)};
        const int n = lat.nearest_node(p);
        REQUIRE(n >= 0);
        const Point2 q = lat.nodes[static_cast<std::size_t>(n)];
        double best = 1e300;
        for (const auto& other : lat.nodes) best = std::min(best, std::hypot(other.x - p.x, other.y - p.y));
        CHECK(std::hypot(q.x - p.x, q.y - p.y) == best);
    }
    const ameoto::TriangularLattice empty;
    CHECK(empty.nearest_node({0, 0}) == -1);
}

namespace {

// The original nearest_node: every node, least squared distance, lowest index on a tie.
int nearest_by_scan(const ameoto::TriangularLattice& lat, Point2 p) {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < lat.nodes.size(); ++i) {
        const double dx = lat.nodes[i].x - p.x, dy = lat.nodes[i].y - p.y;
        const double d2 = dx * dx + dy * dy;
        if (d2 < best_d2) {
            best_d2 = d2;
            best = static_cast<int>(i);
        }
    }
    return best;
}

// Query points that stress the lookup: uniform over a box well beyond the polygon, on its edges and
// vertices, at the nodes, half way along links and at triangle centres (ties between 2 and 3 nodes),
// near those ties by an ulp or so, and far away.
std::vector<Point2> stress_points(const std::vector<PolygonEdge>& poly, const ameoto::TriangularLattice& lat,
                                  ameoto::Random& rng, int random_count) {
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    for (const auto& e : poly) {
        x_lo = std::min(x_lo, e.start.x);
        x_hi = std::max(x_hi, e.start.x);
        y_lo = std::min(y_lo, e.start.y);
        y_hi = std::max(y_hi, e.start.y);
    }
    const double margin = 0.5 * std::max(x_hi - x_lo, y_hi - y_lo);
    std::vector<Point2> points;
    for (int t = 0; t < random_count; ++t)
        points.push_back({rng.uniform(x_lo - margin, x_hi + margin), rng.uniform(y_lo - margin, y_hi + margin)});
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Point2 a = poly[i].start, b = poly[(i + 1) % poly.size()].start;
        points.push_back(a);
        for (int t = 0; t < 200; ++t) {
            const double s = rng.uniform();
            points.push_back({a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)});
        }
    }
    for (const auto& n : lat.nodes) points.push_back(n);
    for (const auto& l : lat.links) {
        const Point2 a = lat.nodes[static_cast<std::size_t>(l.a)], b = lat.nodes[static_cast<std::size_t>(l.b)];
        const Point2 mid{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
        points.push_back(mid);
        points.push_back({std::nextafter(mid.x, 1e300), mid.y});
        points.push_back({mid.x, std::nextafter(mid.y, -1e300)});
        // The third corner of a lattice triangle on this link: its centre is equidistant from three sites.
        const double cx = mid.x - (b.y - a.y) * std::sqrt(3.0) / 6.0, cy = mid.y + (b.x - a.x) * std::sqrt(3.0) / 6.0;
        points.push_back({cx, cy});
        points.push_back({std::nextafter(cx, -1e300), std::nextafter(cy, 1e300)});
    }
    points.push_back({x_lo - 1e3, y_lo + 1e3});
    points.push_back({1e200, -1e200});
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    points.push_back({nan, y_lo});
    points.push_back({x_lo, nan});
    points.push_back({inf, y_lo});
    points.push_back({x_lo, -inf});
    return points;
}

}  // namespace

TEST_CASE("triangular_lattice: the O(1) nearest_node gives exactly the brute force's index") {
    struct Case {
        const char* name;
        std::vector<PolygonEdge> poly;
        std::vector<double> spacings;
    };
    const std::vector<PolygonEdge> sliver = {{{0.0, 0.0}, true}, {{1.0, 0.02}, false}, {{0.05, 0.06}, true}};
    std::vector<PolygonEdge> far_away = triangle(true);   // the lattice far from the origin
    for (auto& e : far_away) e.start = {e.start.x + 1234.5, e.start.y - 987.25};
    const std::vector<Case> cases = {
        {"umbrella panel", umbrella_panel(), {0.04, 0.0617, 0.013, 0.3}},
        {"square", square(1.0, false), {0.1, 0.0999, 0.33, 2.0}},
        {"triangle", triangle(true), {0.05, 0.031, 0.2}},
        {"sliver", sliver, {0.01, 0.02, 0.005}},
        {"far from the origin", far_away, {0.05, 0.0123}},
    };
    ameoto::Random rng(11);
    long checked = 0;
    for (const Case& c : cases) {
        for (const double h : c.spacings) {
            const auto lat = ameoto::build_triangular_lattice(c.poly, h);
            INFO(c.name, ", spacing ", h, ", ", lat.nodes.size(), " nodes");
            CHECK(lat.grid.node_count == lat.nodes.size());
            for (const Point2 p : stress_points(c.poly, lat, rng, 4000)) {
                const int want = nearest_by_scan(lat, p);
                const int got = lat.nearest_node(p);
                if (got != want) {
                    CAPTURE(p.x);
                    CAPTURE(p.y);
                    CHECK(got == want);
                }
                ++checked;
            }
        }
    }
    MESSAGE(checked, " queries, all identical to the brute force");
    CHECK(checked > 50000);
}

TEST_CASE("triangular_lattice: nearest_node falls back to the brute force without a current grid") {
    auto lat = ameoto::build_triangular_lattice(umbrella_panel(), 0.05);
    ameoto::TriangularLattice by_hand;   // no grid: the brute force
    by_hand.nodes = lat.nodes;
    lat.nodes.push_back({0.0, 0.1});     // the grid no longer covers every node: the brute force
    ameoto::Random rng(5);
    for (int t = 0; t < 500; ++t) {
        const Point2 p{rng.uniform(-0.3, 0.3), rng.uniform(-0.1, 0.6)};
        CHECK(by_hand.nearest_node(p) == nearest_by_scan(by_hand, p));
        CHECK(lat.nearest_node(p) == nearest_by_scan(lat, p));
    }
    CHECK(lat.nearest_node({std::nan(""), 0.1}) == -1);   // as the brute force: NaN is nearest nothing
}
