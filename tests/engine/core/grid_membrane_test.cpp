// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/grid_membrane: the triangular-lattice membrane stepped as a stencil over a grid.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "engine/core/grid_membrane.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/core/transverse_network.hpp"
#include "engine/models/membrane.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

namespace {

// An umbrella panel's outline: hem free, ribs fixed (engine/models/canopy.cpp).
std::vector<ameoto::PolygonEdge> panel_outline() {
    const double half = ameoto::constants::pi / 8.0;
    const double w = 0.5 * std::sin(half), h = 0.5 * std::cos(half);
    return {{{-w, 0.0}, false}, {{w, 0.0}, true}, {{0.0, h}, true}};
}

struct Run {
    std::vector<double> net_force;
    std::vector<double> positions;   // every node, every 10th sample
};

// Forces at three nodes at three times (a rain of three drops), then free ringing.
template <typename Body>
Run ring(Body& body, int nodes, int samples) {
    Run run;
    for (int n = 0; n < samples; ++n) {
        if (n == 0) body.apply_force(nodes / 3, 1.0);
        if (n == 7) body.apply_force(nodes / 2, -0.5);
        if (n == 300) {
            body.apply_force(2 * nodes / 3, 0.25);
            body.apply_force(2 * nodes / 3, 0.25);   // two drops on one node in one sample
        }
        run.net_force.push_back(body.step());
        if (n % 10 == 0)
            for (int i = 0; i < nodes; ++i) run.positions.push_back(body.position(i));
    }
    return run;
}

double max_abs(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::fabs(x));
    return m;
}

// Largest difference relative to the reference's peak.
double relative_difference(const std::vector<double>& a, const std::vector<double>& reference) {
    REQUIRE(a.size() == reference.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(a[i] - reference[i]));
    return worst / max_abs(reference);
}

void check_same_as_network(const ameoto::MembraneMaterial& material, int masses, int samples, double tolerance_double,
                           double tolerance_float) {
    ameoto::Membrane membrane = ameoto::build_membrane(panel_outline(), masses, material, kT);
    const auto& lat = membrane.lattice;
    auto grid = ameoto::grid_membrane_over<double>(lat, material.areal_density, material.tension, material.mass_damping,
                                                   material.stiffness_damping, kT);
    auto grid_float = ameoto::grid_membrane_over<float>(lat, material.areal_density, material.tension,
                                                        material.mass_damping, material.stiffness_damping, kT);
    const int n = membrane.network.mass_count();
    REQUIRE(grid.node_count() == n);
    CHECK(grid.stability().sub_steps == membrane.network.stability().sub_steps);
    CHECK(grid.stability().omega_max_bound == doctest::Approx(membrane.network.stability().omega_max_bound).epsilon(1e-12));
    CHECK(grid.stability().gamma_max_bound == ameoto::test::relative(membrane.network.stability().gamma_max_bound).epsilon(1e-12));

    const Run reference = ring(membrane.network, n, samples);
    const Run on_grid = ring(grid, n, samples);
    const Run on_float = ring(grid_float, n, samples);
    CAPTURE(n);
    CAPTURE(grid.stability().sub_steps);
    CHECK(max_abs(reference.positions) > 0.0);
    CHECK(relative_difference(on_grid.net_force, reference.net_force) < tolerance_double);
    CHECK(relative_difference(on_grid.positions, reference.positions) < tolerance_double);
    CHECK(relative_difference(on_float.net_force, reference.net_force) < tolerance_float);
    CHECK(relative_difference(on_float.positions, reference.positions) < tolerance_float);
}

// A body given link by link on a small lattice, built both ways.
struct Spring {
    int a, b;   // b < 0: anchor
    double k;
};

struct SmallBody {
    std::vector<ameoto::AxialIndex> nodes;
    std::vector<Spring> springs;
    double mass = 1e-3, alpha = 10.0, beta = 1e-6;
};

ameoto::TransverseNetwork network_of(const SmallBody& b, double dt) {
    ameoto::TransverseNetwork net;
    for (std::size_t i = 0; i < b.nodes.size(); ++i) net.add_mass(b.mass, b.alpha * b.mass);
    for (const Spring& s : b.springs) {
        if (s.b < 0) net.add_anchor(s.a, s.k, b.beta * s.k);
        else net.add_link(s.a, s.b, s.k, b.beta * s.k);
    }
    net.finalize(dt);
    return net;
}

template <typename Real>
ameoto::BasicGridMembrane<Real> grid_of(const SmallBody& b, double dt) {
    ameoto::BasicGridMembrane<Real> grid(ameoto::GridMembraneBody{b.mass, b.alpha, b.beta});
    for (const auto& a : b.nodes) grid.add_node(a.i, a.j);
    for (const Spring& s : b.springs) {
        if (s.b < 0) grid.add_anchor(s.a, s.k);
        else grid.add_link(s.a, s.b, s.k);
    }
    grid.finalize(dt);
    return grid;
}

// A parallelogram of w x h nodes, every neighbour pair linked with stiffness k(link index), the
// bottom row anchored, the other edges free.
SmallBody parallelogram(int w, int h, double (*k)(int)) {
    SmallBody b;
    auto index = [w](int i, int j) { return j * w + i; };
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) b.nodes.push_back({i, j});
    int l = 0;
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            if (i + 1 < w) b.springs.push_back({index(i, j), index(i + 1, j), k(l++)});
            if (j + 1 < h) b.springs.push_back({index(i, j + 1), index(i, j), k(l++)});   // backward order on purpose
            if (j + 1 < h && i > 0) b.springs.push_back({index(i, j), index(i - 1, j + 1), k(l++)});
        }
    }
    for (int i = 0; i < w; ++i) b.springs.push_back({index(i, 0), -1, 2.0 * k(0)});
    return b;
}

double common_k(int) { return 50.0; }
double varied_k(int l) { return 20.0 + 7.0 * (l % 5); }

}  // namespace

TEST_CASE("grid_membrane: the same body as build_membrane's network gives the same output to rounding") {
    // About 300 masses of nylon at 48 kHz: one sub-step; all three loops of the network against the
    // stencil. Double agrees to rounding; float to its precision (the cost of float, docs/bench.md).
    check_same_as_network(ameoto::MembraneMaterial::nylon_canopy(), 300, 3000, 1e-11, 1e-3);
}

TEST_CASE("grid_membrane: with sub-steps, as the network chooses them") {
    // A hundred times the tension: omega_max T beyond 2, so both take several sub-steps per sample.
    ameoto::MembraneMaterial taut = ameoto::MembraneMaterial::nylon_canopy();
    taut.tension *= 100.0;
    ameoto::Membrane m = ameoto::build_membrane(panel_outline(), 150, taut, kT);
    REQUIRE(m.network.stability().sub_steps > 1);
    check_same_as_network(taut, 150, 2000, 1e-11, 1e-3);
}

TEST_CASE("grid_membrane: links of different stiffness take the general loop, and still agree") {
    for (auto k : {common_k, varied_k}) {
        const SmallBody body = parallelogram(9, 7, k);
        auto net = network_of(body, kT);
        auto grid = grid_of<double>(body, kT);
        const int n = static_cast<int>(body.nodes.size());
        if (k == common_k) {
            CHECK(grid.lattice_cells() == grid.updated_cells());   // one stiffness: the lattice loop only
        } else {
            CHECK(grid.lattice_cells() < grid.updated_cells());    // the general loop serves the rest
        }
        const Run a = ring(net, n, 1500), b = ring(grid, n, 1500);
        CHECK(relative_difference(b.net_force, a.net_force) < 1e-11);
        CHECK(relative_difference(b.positions, a.positions) < 1e-11);
    }
}

TEST_CASE("grid_membrane: free edges have no spring beyond them, fixed points hold the body") {
    SUBCASE("a free body keeps its momentum; the net force is the external force alone") {
        SmallBody body = parallelogram(6, 5, common_k);
        body.springs.erase(std::remove_if(body.springs.begin(), body.springs.end(), [](const Spring& s) { return s.b < 0; }),
                           body.springs.end());
        body.alpha = 0.0;   // no dampers to the ground; the links' dampers are internal
        auto grid = grid_of<double>(body, kT);
        grid.apply_force(4, 2.0);
        CHECK(grid.step() == doctest::Approx(2.0).epsilon(1e-12));
        for (int n = 0; n < 2000; ++n) {
            CHECK(std::fabs(grid.step()) < 1e-9);
            double momentum = 0.0;
            for (int i = 0; i < grid.node_count(); ++i) momentum += body.mass * grid.velocity(i);
            if (n % 500 == 0) CHECK(momentum == ameoto::test::relative(2.0 * kT).epsilon(1e-9));   // impulse F T
        }
    }
    SUBCASE("a lone node with no link drifts; with an anchor it swings back") {
        ameoto::GridMembrane lone(ameoto::GridMembraneBody{1e-3, 0.0, 0.0});
        lone.add_node(0, 0);
        lone.finalize(kT);
        lone.apply_force(0, 1e-3);
        lone.step();
        const double v = lone.velocity(0);
        for (int n = 0; n < 100; ++n) lone.step();
        CHECK(lone.velocity(0) == ameoto::test::relative(v));
        CHECK(lone.position(0) > 100 * v * kT * 0.99);

        ameoto::BasicGridMembrane<double> held(ameoto::GridMembraneBody{1e-3, 0.0, 0.0});
        held.add_node(0, 0);
        const double omega = 0.5 / kT;
        held.add_anchor(0, 1e-3 * omega * omega);
        held.finalize(kT);
        held.apply_force(0, 1e-3);
        double lowest = 0.0;
        for (int n = 0; n < 100; ++n) {
            held.step();
            lowest = std::min(lowest, held.position(0));
        }
        CHECK(lowest < 0.0);   // pulled back through its rest position
    }
    SUBCASE("the anchored row's reaction is the net force once the push has passed") {
        auto grid = grid_of<double>(parallelogram(6, 5, common_k), kT);
        auto net = network_of(parallelogram(6, 5, common_k), kT);
        grid.apply_force(20, 1.0);
        net.apply_force(20, 1.0);
        grid.step();
        net.step();
        double reaction = 0.0;
        for (int n = 0; n < 200; ++n) {
            const double f = grid.step();
            CHECK(f == doctest::Approx(net.step()).epsilon(1e-9).scale(1e-12));
            reaction += std::fabs(f);
        }
        CHECK(reaction > 0.0);
    }
}

TEST_CASE("grid_membrane: stability follows omega T < 2 with the network's margin and sub-steps") {
    const double m = 1e-3;
    for (double wt : {0.5, 1.5, 1.9, 2.5, 3.9, 10.0}) {
        CAPTURE(wt);
        const double omega = wt / kT;
        ameoto::BasicGridMembrane<double> g(ameoto::GridMembraneBody{m, 0.0, 0.0});
        g.add_node(0, 0);
        g.add_anchor(0, m * omega * omega);
        g.finalize(kT);
        const int s = g.stability().sub_steps;
        // The fewest sub-steps with (omega T / s)^2 / 4 < 0.9 (a lone anchored mass: Gershgorin is exact).
        CHECK((wt / s) * (wt / s) / 4.0 < 0.9);
        if (s > 1) CHECK((wt / (s - 1)) * (wt / (s - 1)) / 4.0 >= 0.9);
        CHECK(g.stability().omega_max_bound == doctest::Approx(omega));
        g.apply_force(0, 1.0);
        double peak = 0.0, late = 0.0;
        for (int n = 0; n < 20000; ++n) {
            g.step();
            if (n < 1000) peak = std::max(peak, std::fabs(g.position(0)));
            else late = std::max(late, std::fabs(g.position(0)));
        }
        CHECK(std::isfinite(late));
        CHECK(late < 1.1 * peak);   // undamped and stable: bounded
    }
    ameoto::GridMembrane stiff(ameoto::GridMembraneBody{1e-6, 0.0, 0.0});
    stiff.add_node(0, 0);
    stiff.add_anchor(0, 1e20);
    CHECK_THROWS_AS(stiff.finalize(kT), std::invalid_argument);
}

TEST_CASE("grid_membrane: step and apply_force never allocate") {
    ameoto::Membrane membrane = ameoto::build_membrane(panel_outline(), 200, ameoto::MembraneMaterial::nylon_canopy(), kT);
    const auto& mat = membrane.material;
    auto grid = ameoto::grid_membrane_over(membrane.lattice, mat.areal_density, mat.tension, mat.mass_damping,
                                           mat.stiffness_damping, kT);
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope s;
        for (int n = 0; n < 500; ++n) {
            for (int node = 0; node < grid.node_count(); node += 7) grid.apply_force(node, 1e-3);
            grid.step();
        }
        grid.reset();
        grid.step();
    }
    CHECK(audit.entries() > 0);
    CHECK(audit.violations() == 0);
    CHECK(audit.first() == "none");
}

TEST_CASE("grid_membrane: a copy steps like the original; reset brings it to rest") {
    auto a = grid_of<float>(parallelogram(5, 4, common_k), kT);
    a.apply_force(3, 1.0);
    a.step();
    auto b = a;   // canopies copy a prototype body
    for (int n = 0; n < 50; ++n) CHECK(a.step() == b.step());
    CHECK(a.position(7) == b.position(7));
    CHECK(a.finite());
    a.reset();
    for (int i = 0; i < a.node_count(); ++i) CHECK(a.position(i) == 0.0);
    CHECK(a.step() == 0.0);
}

TEST_CASE("grid_membrane: refuses what is not a lattice membrane") {
    ameoto::GridMembrane g;
    const int a = g.add_node(0, 0), b = g.add_node(2, 0), c = g.add_node(1, 1);
    CHECK_THROWS_AS(g.add_link(a, b, 1.0), std::invalid_argument);   // not neighbours
    CHECK_THROWS_AS(g.add_link(a, c, 1.0), std::invalid_argument);   // (1, 1) is not a lattice direction
    CHECK_THROWS_AS(g.add_link(a, a, 1.0), std::invalid_argument);
    CHECK_THROWS_AS(g.add_anchor(5, 1.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::GridMembrane(ameoto::GridMembraneBody{0.0, 0.0, 0.0}), std::invalid_argument);
    ameoto::GridMembrane twice;
    twice.add_node(1, 1);
    twice.add_node(1, 1);
    CHECK_THROWS_AS(twice.finalize(kT), std::invalid_argument);
}

TEST_CASE("grid_membrane: axial coordinates recover the lattice's neighbours") {
    const auto lat = ameoto::build_triangular_lattice(panel_outline(), 0.05);
    const auto axial = ameoto::axial_coordinates(lat);
    REQUIRE(axial.size() == lat.nodes.size());
    for (const auto& l : lat.links) {
        const int di = axial[static_cast<std::size_t>(l.b)].i - axial[static_cast<std::size_t>(l.a)].i;
        const int dj = axial[static_cast<std::size_t>(l.b)].j - axial[static_cast<std::size_t>(l.a)].j;
        const bool neighbour = (di == 1 && dj == 0) || (di == 0 && dj == 1) || (di == -1 && dj == 1);
        CHECK(neighbour);
    }
}
