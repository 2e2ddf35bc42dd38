// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/symplectic_euler: warping, shadow energy, equivalence with CORDIS.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

TEST_CASE("symplectic_euler: an oscillator's frequency follows cos(omega T) = 1 - omega0^2 T^2 / 2") {
    for (double w0t : {0.5, 1.0, 1.9}) {
        CAPTURE(w0t);
        const double omega0 = w0t / kT;
        auto net = one_oscillator(1e-3, omega0);
        net.finalize(kT, options_for(Integrator::symplectic_euler, StabilityPolicy::none));
        REQUIRE(net.integrator() == Integrator::symplectic_euler);
        net.apply_force(0, 1.0);
        std::vector<double> x;
        for (int n = 0; n < 100000; ++n) {
            net.step();
            x.push_back(net.position(0));
        }
        // symplectic_euler.hpp: acos(1 - w0^2 T^2 / 2) / T = (2/T) asin(w0 T / 2); 0.1 %.
        const double expected = std::acos(1.0 - 0.5 * w0t * w0t) / kT;
        CHECK(expected == doctest::Approx((2.0 / kT) * std::asin(w0t / 2.0)).epsilon(1e-12));
        CHECK(zero_crossing_omega(x, kT) == doctest::Approx(expected).epsilon(1e-3));
    }
}

TEST_CASE("symplectic_euler: conserves its shadow energy to rounding and equals the CORDIS scheme") {
    // Undamped membrane patch at omega_max T ~ 0.3.
    auto body = lattice_membrane(20);
    auto other = lattice_membrane(20);
    body.network.finalize(kT, options_for(Integrator::symplectic_euler));
    other.network.finalize(kT, options_for(Integrator::explicit_verlet));
    const auto& a = body.network.arrays();
    const int n = body.network.mass_count();
    auto shadow = [&] {
        // symplectic_euler.hpp: H = 1/2 v'Mv + 1/2 x'Kx - (T/2) v'K x.
        std::vector<double> x(static_cast<std::size_t>(n)), v(x), kx(x);
        for (int i = 0; i < n; ++i) {
            x[static_cast<std::size_t>(i)] = body.network.position(i);
            v[static_cast<std::size_t>(i)] = body.network.velocity(i);
        }
        a.forces(x.data(), nullptr, nullptr, kx.data());   // -K x
        double vkx = 0.0;
        for (int i = 0; i < n; ++i) vkx -= v[static_cast<std::size_t>(i)] * kx[static_cast<std::size_t>(i)];
        return a.energy(x.data(), v.data()) - 0.5 * kT * vkx;
    };
    body.network.apply_force(3, 0.2);
    other.network.apply_force(3, 0.2);
    body.network.step();
    other.network.step();
    const double h0 = shadow(), e0 = body.network.kinetic_plus_potential_energy();
    double worst_h = 0.0, worst_e = 0.0, worst_x = 0.0, scale = 0.0;
    for (int s = 0; s < 20000; ++s) {
        body.network.step();
        other.network.step();
        if (s % 7 == 0) worst_h = std::max(worst_h, std::abs(shadow() - h0) / h0);
        worst_e = std::max(worst_e, std::abs(body.network.kinetic_plus_potential_energy() - e0) / e0);
        for (int i = 0; i < n; ++i) {
            worst_x = std::max(worst_x, std::abs(body.network.position(i) - other.network.position(i)));
            scale = std::max(scale, std::abs(other.network.position(i)));
        }
    }
    // Shadow energy: rounding only, 1e-10 relative over 2e4 steps.
    CHECK(worst_h < 1e-10);
    // The plain energy oscillates by up to ~omega_max T / 2 (here ~0.15) but does not drift.
    CHECK(worst_e < 0.5 * body.network.stability().omega_max_estimate * kT + 1e-3);
    // symplectic_euler.hpp: algebraically the CORDIS scheme; the trajectories agree to rounding
    // (1e-9 of the motion's size after 2e4 steps: ~eps per step, growing linearly).
    CHECK(worst_x <= 1e-9 * scale);
}
