// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/trapezoidal: atan warping, energy conservation, unconditional stability.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

TEST_CASE("trapezoidal: an oscillator's frequency follows (2/T) atan(omega0 T / 2)") {
    for (double w0t : {0.5, 2.0, 5.0, 10.0}) {
        CAPTURE(w0t);
        const double omega0 = w0t / kT;
        auto net = one_oscillator(1e-3, omega0);
        net.finalize(kT, options_for(Integrator::trapezoidal));
        REQUIRE(net.stability().sub_steps == 1);
        net.apply_force(0, 1.0);
        std::vector<double> x;
        for (int n = 0; n < 100000; ++n) {
            net.step();
            x.push_back(net.position(0));
        }
        // physics.md s.3, s.5 check 4: omega = (2/T) atan(omega0 T / 2); 0.1 % (brief).
        CHECK(zero_crossing_omega(x, kT) == doctest::Approx((2.0 / kT) * std::atan(w0t / 2.0)).epsilon(1e-3));
    }
}

TEST_CASE("trapezoidal: energy is conserved to rounding at any step, even omega_max T = 100") {
    auto body = lattice_membrane(20);
    const double omega_max = power_iteration_omega_max(body.network.arrays());
    const double t = 100.0 / omega_max;
    body.network.finalize(t, options_for(Integrator::trapezoidal));
    body.network.apply_force(5, 1.0);
    body.network.step();
    const double e0 = body.network.kinetic_plus_potential_energy();
    double worst = 0.0;
    for (int n = 0; n < 20000; ++n) {
        body.network.step();
        worst = std::max(worst, std::abs(body.network.kinetic_plus_potential_energy() - e0) / e0);
    }
    // trapezoidal.hpp: a Cayley transform, orthogonal in the energy norm: rounding only (1e-10 over 2e4
    // steps; the solve's backward error per step is ~1e-15).
    CHECK(worst < 1e-10);
    CHECK(body.network.finite());
}

TEST_CASE("trapezoidal: Newmark average acceleration with a held force: a free mass moves as T^2 f / 2m") {
    // Free mass, force f held for one step: x[1] = (T^2/4)(a0 + a1) = T^2 f / (2m), v[1] = T f / m
    // (trapezoidal.hpp: both ends of the step see the force).
    TransverseNetwork net;
    net.add_mass(2e-3, 0.0);
    net.finalize(kT, options_for(Integrator::trapezoidal));
    net.apply_force(0, 3.0);
    const double f = net.step();
    CHECK(f == doctest::Approx(3.0).epsilon(1e-14));   // momentum change over T: rounding only
    CHECK(net.position(0) == ameoto::test::relative(kT * kT * 3.0 / (2.0 * 2e-3)).epsilon(1e-14));
    CHECK(net.velocity(0) == ameoto::test::relative(kT * 3.0 / 2e-3).epsilon(1e-14));
    net.step();   // no force: coasts
    CHECK(net.position(0) == ameoto::test::relative(kT * kT * 3.0 / (2.0 * 2e-3) + kT * kT * 3.0 / 2e-3).epsilon(1e-14));
}
