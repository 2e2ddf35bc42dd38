// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared by the integrator tests: small bodies (one oscillator, a triangular-lattice membrane, a free
// chain), a frequency meter, and the switch that prints the measured tables.
//
//   auto net = one_oscillator(m, omega0, z);              // not finalized
//   LatticeBody b = lattice_membrane(masses, s, T, alpha, beta);   // ~masses, fixed + one free edge
//   zero_crossing_omega(x, dt)                            // rad/s from a recorded oscillation
//   options_for(Integrator, policy)                       // NetworkOptions
//   print_tables()                                        // AMEOTO_PRINT_TABLES set: print markdown

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

#include "engine/core/transverse_network.hpp"
#include "engine/core/triangular_lattice.hpp"
#include "tests/support/test_constants.hpp"

namespace ameoto::test {

using common::kPi;

inline bool print_tables() { return std::getenv("AMEOTO_PRINT_TABLES") != nullptr; }

inline NetworkOptions options_for(Integrator integrator, StabilityPolicy policy = StabilityPolicy::sub_step) {
    NetworkOptions o;
    o.integrator = integrator;
    o.stability.policy = policy;
    return o;
}

// One mass m on an anchor spring m omega0^2, with a ground damper z.
inline TransverseNetwork one_oscillator(double m, double omega0, double z = 0.0) {
    TransverseNetwork net;
    const int a = net.add_mass(m, z);
    net.add_anchor(a, m * omega0 * omega0, 0.0);
    return net;
}

// Angular frequency (rad/s) of a recorded oscillation from its zero crossings (linearly interpolated):
// (crossings - 1) half periods between the first and the last crossing.
inline double zero_crossing_omega(const std::vector<double>& x, double dt) {
    double first = -1.0, last = -1.0;
    int crossings = 0;
    for (std::size_t n = 1; n < x.size(); ++n) {
        const double a = x[n - 1], b = x[n];
        if ((a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0)) {
            if (b == 0.0 && n + 1 < x.size() && (x[n + 1] > 0.0) == (a > 0.0)) continue;   // touch, no cross
            const double t = (static_cast<double>(n - 1) + a / (a - b)) * dt;
            if (crossings == 0) first = t;
            last = t;
            ++crossings;
        }
    }
    REQUIRE(crossings > 10);
    return kPi * (crossings - 1) / (last - first);
}

// A membrane patch as a triangular lattice (core/triangular_lattice.hpp) over an irregular quadrilateral
// with three fixed edges and one free: springs k = T / sqrt 3, masses s A, Rayleigh damping alpha M +
// beta K (the construction of models/membrane.cpp, rebuilt here so core tests need no model).
struct LatticeBody {
    TriangularLattice lattice;
    TransverseNetwork network;
};

inline LatticeBody lattice_membrane(int masses, double s = 0.06, double tension = 1000.0, double alpha = 0.0,
                                    double beta = 0.0) {
    const std::vector<PolygonEdge> outline = {{{0.0, 0.0}, false}, {{0.21, 0.01}, true}, {{0.19, 0.17}, true}, {{0.02, 0.15}, true}};
    LatticeBody b;
    b.lattice = build_triangular_lattice(outline, spacing_for_node_count(outline, masses));
    const double k = tension / std::sqrt(3.0), m = s * b.lattice.node_area, z = beta * k;
    for (std::size_t i = 0; i < b.lattice.nodes.size(); ++i) {
        const int node = b.network.add_mass(m, alpha * m);
        const int anchors = b.lattice.anchor_links[i];
        if (anchors > 0) b.network.add_anchor(node, anchors * k, anchors * z);
    }
    for (const auto& l : b.lattice.links) b.network.add_link(l.a, l.b, k, z);
    return b;
}

// Three masses in a chain with springs and dampers, no anchor, no ground: a free body.
inline TransverseNetwork free_chain() {
    TransverseNetwork net;
    net.add_mass(1e-3, 0.0);
    net.add_mass(3e-3, 0.0);
    net.add_mass(2e-3, 0.0);
    net.add_link(0, 1, 500.0, 0.01);
    net.add_link(1, 2, 800.0, 0.02);
    net.add_link(0, 2, 300.0, 0.0);
    return net;
}

}  // namespace ameoto::test
