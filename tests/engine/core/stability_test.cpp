// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/stability: bounds before a body runs, the policies, the runtime guard.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "engine/core/modal_decomposition.hpp"
#include "engine/core/stability.hpp"
#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A stiff anchored chain: omega_max T ~ 10 at 48 kHz.
TransverseNetwork stiff_chain(double z = 0.0) {
    TransverseNetwork net;
    const double m = 1e-3, k = m * std::pow(5.0 / kT, 2);
    for (int i = 0; i < 6; ++i) net.add_mass(m, z);
    net.add_anchor(0, k, 0.0);
    for (int i = 0; i < 5; ++i) net.add_link(i, i + 1, k, 0.0);
    net.add_anchor(5, k, 0.0);
    return net;
}

}  // namespace

TEST_CASE("stability: Gershgorin bounds omega_max from above, power iteration finds it") {
    for (int masses : {20, 60}) {
        auto body = lattice_membrane(masses, 0.06, 1000.0, 20.0, 2e-6);
        const auto& a = body.network.arrays();
        const double exact = decompose_modes(a).omega.maxCoeff();
        const double gersh = gershgorin_omega_max(a), power = power_iteration_omega_max(a);
        CAPTURE(masses);
        // stability.hpp: Gershgorin is an upper bound; the power iteration's Rayleigh quotient is a lower
        // bound, converged here to 1e-6 relative (stopping rule 1e-13 per iteration, three in a row).
        CHECK(gersh >= exact);
        CHECK(power <= exact * (1.0 + 1e-12));
        CHECK(power == doctest::Approx(exact).epsilon(1e-6));
        // A triangular lattice: the interior bound is sqrt(12 k / m), the lattice's top sqrt(9 k / m) in the
        // bulk; a finite patch sits between (stability.hpp): the bound is 5..20 % above the truth.
        CHECK(gersh / exact > 1.05);
        CHECK(gersh / exact < 1.2);
        // Damping bound: Gershgorin on M^-1 C, alpha + beta * (12 k / m) at most (membrane.hpp's Rayleigh).
        const double k = 1000.0 / std::sqrt(3.0), m = a.mass(0);
        CHECK(gershgorin_gamma_max(a) <= 20.0 + 2e-6 * 12.0 * k / m * (1.0 + 1e-12));
    }
}

TEST_CASE("stability: the policies when omega_max T exceeds 2") {
    SUBCASE("refuse names the bound") {
        auto net = stiff_chain();
        NetworkOptions o = options_for(Integrator::explicit_verlet, StabilityPolicy::refuse);
        try {
            net.finalize(kT, o);
            FAIL("a network at omega_max T ~ 10 must be refused");
        } catch (const StabilityError& e) {
            const std::string what = e.what();
            // stability.hpp: "omega_max T = ... exceeds 2 for the explicit Verlet scheme; use sub-steps or
            // an implicit method".
            CHECK(contains(what, "omega_max T = 10 exceeds 2 for the explicit Verlet scheme"));
            CHECK(contains(what, "use sub-steps or an implicit method"));
            CHECK(contains(what, "power iteration"));
        }
        CHECK(net.stability().refused);
        CHECK(net.stability().omega_max_bound * kT == doctest::Approx(10.0).epsilon(1e-12));   // 2 sqrt(k/m) T
    }
    SUBCASE("sub_step takes the fewest sub-steps") {
        auto net = stiff_chain();
        net.finalize(kT);
        const auto& r = net.stability();
        CHECK(r.integrator == Integrator::explicit_verlet);
        CHECK(r.margin() < 0.9);
        StabilityReport fewer = r;
        fewer.sub_steps = r.sub_steps - 1;
        CHECK(fewer.margin() >= 0.9);
        CHECK(r.sub_steps == 6);   // (10 / n)^2 / 4 < 0.9: n > 5.27 (Gershgorin's omega_max T = 10)
        CHECK(contains(r.message, "running 6 sub-steps"));
    }
    SUBCASE("the tight estimate saves sub-steps") {
        auto net = stiff_chain();
        NetworkOptions o;
        o.stability.bound = StabilityBound::power_iteration;
        net.finalize(kT, o);
        // Chain of 6 anchored at both ends: omega_max^2 = (k/m)(2 - 2 cos(6 pi / 7)) = 3.80 k/m vs 4 k/m.
        const double exact = std::sqrt(25.0 * (2.0 - 2.0 * std::cos(6.0 * kPi / 7.0))) / kT;
        CHECK(net.stability().omega_max_estimate == doctest::Approx(exact).epsilon(1e-9));
        CHECK(net.stability().sub_steps == 6);   // 9.75 / sqrt 3.6 = 5.14: still 6
        CHECK(net.stability().margin() < 0.9);
    }
    SUBCASE("switch_to_stable runs the trapezoidal rule") {
        auto net = stiff_chain();
        net.finalize(kT, options_for(Integrator::explicit_verlet, StabilityPolicy::switch_to_stable));
        CHECK(net.stability().requested == Integrator::explicit_verlet);
        CHECK(net.integrator() == Integrator::trapezoidal);
        CHECK(net.stability().sub_steps == 1);
        CHECK(contains(net.stability().message, "switched to trapezoidal"));
        net.apply_force(2, 1.0);
        for (int n = 0; n < 1000; ++n) CHECK(std::isfinite(net.step()));
        CHECK(net.finite());
    }
    SUBCASE("none runs it as asked, and it diverges") {
        auto net = stiff_chain();
        NetworkOptions o = options_for(Integrator::explicit_verlet, StabilityPolicy::none);
        o.guard.enabled = false;
        net.finalize(kT, o);
        CHECK(net.stability().sub_steps == 1);
        CHECK(contains(net.stability().message, "running anyway"));
        net.apply_force(2, 1.0);
        int n = 0;
        while (net.finite() && n < 10000) {
            net.step();
            ++n;
        }
        CHECK_FALSE(net.finite());   // omega T = 10: the highest mode grows ~ 100x per step
        CHECK(n < 500);
    }
    SUBCASE("too many sub-steps is a refusal") {
        auto net = stiff_chain();
        NetworkOptions o;
        o.stability.max_sub_steps = 5;
        CHECK_THROWS_AS(net.finalize(kT, o), StabilityError);
        CHECK(contains(net.stability().message, "needs 6 sub-steps, more than the limit 5"));
    }
}

TEST_CASE("stability: the damped bound omega^2 T^2 + 2 gamma T < 4") {
    // omega0 T = 1.2 alone is fine (0.36); gamma T = 1.5 pushes the margin to (1.44 + 3) / 4 = 1.11.
    const double m = 1e-3;
    auto net = one_oscillator(m, 1.2 / kT, 1.5 * m / kT);
    const auto r = assess_stability(net.arrays(), kT, Integrator::symplectic_euler, StabilityOptions{StabilityPolicy::refuse});
    CHECK(r.refused);
    CHECK(r.margin() == ameoto::test::relative((1.44 + 3.0) / 4.0).epsilon(1e-12));   // exact for one mass
    CHECK(contains(r.message, "omega_max^2 T^2 + 2 gamma_max T = 4.44"));
    CHECK(contains(r.message, "symplectic Euler"));
}

TEST_CASE("stability: implicit and modal schemes are never refused") {
    for (auto i : {Integrator::trapezoidal, Integrator::backward_euler, Integrator::modal}) {
        auto net = stiff_chain();
        net.finalize(kT, options_for(i, StabilityPolicy::refuse));
        CHECK(net.integrator() == i);
        CHECK_FALSE(net.stability().refused);
        CHECK(net.stability().sub_steps == 1);
        CHECK(contains(net.stability().message, i == Integrator::modal ? "exact at any step" : "unconditionally stable"));
        CHECK(contains(net.stability().message, "omega_max T = 10"));   // the bound is still reported
    }
}

TEST_CASE("stability: the runtime guard's limit follows the injected amplitude") {
    RuntimeGuard g;
    GuardOptions forgetting;
    forgetting.memory_s = 10.0;
    g.configure(forgetting, kT);
    CHECK(g.energy_limit() == 0.0);
    CHECK_FALSE(g.exceeded(true, 0.0));
    CHECK(g.exceeded(true, 1e-30));       // energy with nothing injected
    CHECK(g.exceeded(false, 0.0));        // non-finite state
    g.inject(3.0);
    g.inject(4.0);
    // stability.hpp: A = sum of sqrt(e_n), forgotten by exp(-T / 10 s) per step; limit 1e6 A^2.
    CHECK(g.energy_limit() == doctest::Approx(1e6 * std::pow(3.0 * std::exp(-kT / 10.0) + 4.0, 2)).epsilon(1e-14));
    CHECK_FALSE(g.exceeded(true, 4.8e7));
    CHECK(g.exceeded(true, 5e7));
    CHECK(g.exceeded(true, std::nan("")));
    for (int n = 0; n < 480000; ++n) g.inject(0.0);   // 10 s: A falls by e
    CHECK(g.energy_limit() == doctest::Approx(1e6 * std::pow((3.0 * std::exp(-kT / 10.0) + 4.0) * std::exp(-1.0), 2)).epsilon(1e-9));
    RuntimeGuard never;   // default: never forgets (stability.hpp)
    never.configure(GuardOptions{}, kT);
    never.inject(3.0);
    for (int n = 0; n < 480000; ++n) never.inject(0.0);
    CHECK(never.energy_limit() == 9e6);
    GuardOptions fixed;
    fixed.energy_limit_J = 2.0;
    g.configure(fixed, kT);
    CHECK(g.energy_limit() == 2.0);
    CHECK(g.exceeded(true, 2.5));
    GuardOptions off;
    off.enabled = false;
    g.configure(off, kT);
    CHECK_FALSE(g.exceeded(false, 1e300));
}
