// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/backward_euler: unconditional stability and monotone energy loss.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

TEST_CASE("backward_euler: energy decreases monotonically, faster at larger omega T") {
    auto body = lattice_membrane(20);   // undamped: all loss is numerical
    body.network.finalize(kT, options_for(Integrator::backward_euler));
    body.network.apply_force(4, 1.0);
    body.network.step();
    double previous = body.network.kinetic_plus_potential_energy();
    const double e0 = previous;
    int increases = 0;
    for (int n = 0; n < 20000; ++n) {
        body.network.step();
        const double e = body.network.kinetic_plus_potential_energy();
        increases += e > previous;
        previous = e;
    }
    // backward_euler.hpp: E[n+1] - E[n] = -1/2 (dv'M dv + dx'K dx) <= 0 at every step, exactly.
    CHECK(increases == 0);
    CHECK(previous < 0.5 * e0);
}

TEST_CASE("backward_euler: an oscillator's poles are 1 / (1 -+ i omega0 T)") {
    for (double w0t : {0.1, 1.0, 10.0}) {
        CAPTURE(w0t);
        auto net = one_oscillator(1e-3, w0t / kT);
        net.finalize(kT, options_for(Integrator::backward_euler));
        net.apply_force(0, 1.0);
        std::vector<double> x;
        for (int n = 0; n < 3; ++n) {
            net.step();
            x.push_back(net.position(0));
        }
        // A two-pole free response obeys x[n+1] = 2 Re(p) x[n] - |p|^2 x[n-1] with p = 1 / (1 - i w0 T):
        // Re p = 1 / (1 + w0^2 T^2) = |p|^2 (backward_euler.hpp). Rounding only.
        const double r = 1.0 / (1.0 + w0t * w0t);
        CHECK(x[2] == doctest::Approx(2.0 * r * x[1] - r * x[0]).epsilon(1e-10).scale(std::abs(x[0])));
    }
}
