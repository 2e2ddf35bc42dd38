// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/explicit_verlet: the CORDIS scheme's warping and sub-steps.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

TEST_CASE("explicit_verlet: an oscillator's frequency follows (2/T) asin(omega0 T / 2)") {
    for (double w0t : {0.5, 1.0, 1.9}) {
        CAPTURE(w0t);
        const double omega0 = w0t / kT;
        auto net = one_oscillator(1e-3, omega0);
        // 1.9^2 / 4 = 0.90 is past the default 0.9 safety, so the sub-step policy would add a sub-step:
        // run it as asked (policy none) to measure the scheme itself at omega0 T = 1.9.
        net.finalize(kT, options_for(Integrator::explicit_verlet, StabilityPolicy::none));
        REQUIRE(net.stability().sub_steps == 1);
        net.apply_force(0, 1.0);
        std::vector<double> x;
        for (int n = 0; n < 100000; ++n) {
            net.step();
            x.push_back(net.position(0));
        }
        // physics.md s.3, s.5 check 4: omega = (2/T) asin(omega0 T / 2), 0.1 % (brief).
        const double expected = (2.0 / kT) * std::asin(w0t / 2.0);
        CHECK(zero_crossing_omega(x, kT) == doctest::Approx(expected).epsilon(1e-3));
        // The warping is real: 1 % or more away from omega0 at omega0 T >= 1 (4.3 % at 1, 45 % at 1.9).
        if (w0t >= 1.0) CHECK(std::abs(zero_crossing_omega(x, kT) / omega0 - 1.0) > 0.01);
    }
}

TEST_CASE("explicit_verlet: sub-steps hold the force; the net force is the momentum change over T") {
    // A stiff oscillator (omega0 T = 3) gets sub-steps; the impulse over one output step is T f exactly,
    // and step() returns sum m dv / T.
    const double m = 2e-3, omega0 = 3.0 / kT;
    auto net = one_oscillator(m, omega0);
    net.finalize(kT);
    REQUIRE(net.stability().sub_steps == 2);   // fewest n with (3/n)^2 / 4 < 0.9: 2.25, then 0.5625 (stability.hpp)
    net.apply_force(0, 0.5);
    double v0 = 0.0;
    for (int n = 0; n < 50; ++n) {
        const double f = net.step();
        const double v1 = net.velocity(0);
        // explicit_verlet.hpp: net force = m (v[n+1] - v[n]) / T over the output step (rounding; the
        // velocities are backward differences of sub-steps, so compare on the scale of m |v| / T).
        CHECK(f == doctest::Approx(m * (v1 - v0) / kT).epsilon(1e-9).scale(m * 1e-3 / kT));
        v0 = v1;
    }
}
