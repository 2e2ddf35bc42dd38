// SPDX-License-Identifier: GPL-3.0-or-later
// The stability map's claims, tested: every method the engine offers stays bounded where it claims to
// (integrators/integrator.hpp, stability.hpp), and the runtime guard catches the one run outside its
// bound (explicit Verlet at omega_max T = 2.2): the body is reset and the output never explodes.
// The body: a fixed-fixed chain of 8 equal masses, omega_max = 2 sqrt(k/m) sin(8 pi / 18) in closed form
// (the eigenvalues of the second-difference matrix, 2 - 2 cos(j pi / 9), j = 1..8).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/core/transverse_network.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

using namespace ameoto;

namespace {

constexpr int kMasses = 8;
constexpr double kMass = 1e-3, kStiffness = 1000.0;

double chain_omega_max() { return 2.0 * std::sqrt(kStiffness / kMass) * std::sin(kMasses * kPi / (2.0 * (kMasses + 1))); }

TransverseNetwork chain_with(const NetworkOptions& o, double omega_max_t) {
    TransverseNetwork net;
    for (int i = 0; i < kMasses; ++i) net.add_mass(kMass, 0.0);
    for (int i = 0; i + 1 < kMasses; ++i) net.add_link(i, i + 1, kStiffness, 0.0);
    net.add_anchor(0, kStiffness, 0.0);
    net.add_anchor(kMasses - 1, kStiffness, 0.0);
    net.finalize(omega_max_t / chain_omega_max(), o);
    return net;
}

// Built at the step that puts omega_max T where asked, policy none: the scheme runs as it is.
TransverseNetwork chain(Integrator integrator, double omega_max_t, GuardOptions guard = {.enabled = false}) {
    NetworkOptions o;
    o.integrator = integrator;
    o.stability.policy = StabilityPolicy::none;
    o.guard = guard;
    return chain_with(o, omega_max_t);
}

struct EnergyRun {
    double first = 0.0, worst = 0.0, worst_late = 0.0;   // E after the strike; max E; max E over the last 10 %
    bool monotone = true, finite = true;
};

// Struck at one end (every mode excited), then free for `steps`.
EnergyRun run_free(TransverseNetwork& net, int steps) {
    EnergyRun r;
    net.apply_force(0, 1.0);
    net.step();
    r.first = net.kinetic_plus_potential_energy();
    double previous = r.first;
    for (int n = 0; n < steps; ++n) {
        net.step();
        const double e = net.kinetic_plus_potential_energy();
        r.finite = r.finite && net.finite() && std::isfinite(e);
        r.worst = std::max(r.worst, e);
        if (n >= steps - steps / 10) r.worst_late = std::max(r.worst_late, e);
        r.monotone = r.monotone && e <= previous * (1.0 + 1e-12);
        previous = e;
    }
    return r;
}

}  // namespace

TEST_CASE("stability map: the chain's omega_max is the closed form (power iteration agrees)") {
    const TransverseNetwork net = chain(Integrator::explicit_verlet, 1.0);
    CHECK(power_iteration_omega_max(net.arrays()) == doctest::Approx(chain_omega_max()).epsilon(1e-9));
}

TEST_CASE("stability map: explicit Verlet and symplectic Euler stay bounded at omega_max T = 1.9") {
    for (Integrator integrator : {Integrator::explicit_verlet, Integrator::symplectic_euler}) {
        CAPTURE(std::string(integrator_name(integrator)));
        TransverseNetwork net = chain(integrator, 1.9);
        const EnergyRun r = run_free(net, 100000);
        REQUIRE(r.finite);
        // Bounded: the measured energy ripples around the scheme's conserved shadow energy (by a factor up
        // to about 1 / (1 - (omega T / 2)^2) = 10 for the top mode at 1.9) but never trends: the last
        // 10 % of 10^5 steps is no worse than the whole, and far below the growth an unstable mode shows
        // (at 2.2 the amplitude grows 2.4x a step: 10^5 steps would overflow).
        CHECK(r.worst_late <= r.worst);
        CHECK(r.worst < 100.0 * r.first);
    }
}

TEST_CASE("stability map: trapezoidal, backward Euler and modal stay bounded at omega_max T = 10") {
    {
        TransverseNetwork net = chain(Integrator::trapezoidal, 10.0);
        const EnergyRun r = run_free(net, 100000);
        REQUIRE(r.finite);
        // trapezoidal.hpp: energy conserved to rounding at any omega T for linear links.
        CHECK(r.worst <= r.first * (1.0 + 1e-9));
    }
    {
        TransverseNetwork net = chain(Integrator::backward_euler, 10.0);
        const EnergyRun r = run_free(net, 100000);
        REQUIRE(r.finite);
        CHECK(r.monotone);   // backward_euler.hpp: E[n+1] <= E[n] at every step
        CHECK(r.worst <= r.first);
    }
    {
        TransverseNetwork net = chain(Integrator::modal, 10.0);
        const EnergyRun r = run_free(net, 100000);
        REQUIRE(r.finite);
        // modal.hpp: every mode advanced exactly; undamped, the modal energy is constant to rounding.
        CHECK(r.worst <= r.first * (1.0 + 1e-9));
    }
}

TEST_CASE("stability map: explicit Verlet at omega_max T = 2.2 grows without the guard") {
    TransverseNetwork net = chain(Integrator::explicit_verlet, 2.2);
    const EnergyRun r = run_free(net, 200);
    // The top mode's amplitude factor per step is |z| = h + sqrt(h^2 - 1), h = (2.2^2 - 2) / 2 = 1.42:
    // 2.43. Over 200 steps the energy grows by far more than 10^100 (or overflows).
    CHECK((!r.finite || r.worst > 1e100 * r.first));
}

TEST_CASE("stability map: the guard catches explicit Verlet at omega_max T = 2.2, and the output stays bounded") {
    GuardOptions guard;
    guard.check_every_steps = 1;   // the guard after every step: nothing escapes into the output
    TransverseNetwork net = chain(Integrator::explicit_verlet, 2.2, guard);
    double loudest = 0.0;
    bool finite = true;
    for (int n = 0; n < 48000; ++n) {
        if (n % 4800 == 0) net.apply_force(n % 8, 1.0);   // 1 N for one sample every 0.1 s
        const double f = net.step();
        finite = finite && std::isfinite(f);
        loudest = std::max(loudest, std::abs(f));
    }
    CHECK(finite);
    CHECK(net.guard_resets() >= 10);   // every strike runs away and is caught
    // Bounded by the guard's own limit: it resets the chain in the step its energy passes E_lim = 1e6 A^2
    // (stability.hpp; A the injected amplitude, at most the 10 strikes' sum, each T f / sqrt(2 m)), so no
    // step starts above E_lim; one step grows the amplitude 2.43x at most, and the net force is a momentum
    // change over T, where |P| <= sqrt(2 E M) (Cauchy-Schwarz, M the total mass). So
    // |f| <= (1 + 2.43) sqrt(2 E_lim M) / T. (Without the guard: 1e100 and more, the case above.)
    const double total_mass = kMasses * kMass, t = 2.2 / chain_omega_max();
    const double amplitude = 10.0 * t * 1.0 / std::sqrt(2.0 * kMass);
    const double bound = 3.43 * std::sqrt(2.0 * 1e6 * amplitude * amplitude * total_mass) / t;
    MESSAGE("loudest net force " << loudest << " N, bound " << bound << " N");
    CHECK(loudest <= bound);
    CHECK(net.finite());
}

TEST_CASE("stability map: explicit Verlet at omega_max T = 2.2, guarded by its owner once per 64-sample block") {
    // As the canopy is guarded (the renderer calls guard() after every block): the body is reset and
    // comes back finite and quiet after each runaway.
    TransverseNetwork net = chain(Integrator::explicit_verlet, 2.2, GuardOptions{});
    net.apply_force(3, 1.0);
    for (int n = 0; n < 64; ++n) net.step();
    CHECK(net.guard());
    CHECK(net.guard_resets() == 1);
    CHECK(net.finite());
    CHECK(net.kinetic_plus_potential_energy() == 0.0);
    for (int n = 0; n < 64; ++n) CHECK(net.step() == 0.0);   // silent until struck again
}

TEST_CASE("stability map: the default policy never runs explicit Verlet beyond its bound") {
    // What the engine builds unless told otherwise (policy sub_step): at omega_max T = 2.2 it sub-steps
    // until the margin is below 0.9, so the runaway above cannot happen in a built scene.
    TransverseNetwork net = chain_with(NetworkOptions{}, 2.2);
    CHECK(net.stability().sub_steps >= 2);
    CHECK(net.stability().margin() < 0.9);
    const EnergyRun r = run_free(net, 20000);
    CHECK(r.finite);
    CHECK(r.worst_late <= r.worst);
}

TEST_CASE("stability: min_sub_steps oversamples an explicit scheme and leaves the others alone") {
    NetworkOptions o;
    o.stability.min_sub_steps = 4;
    const TransverseNetwork oversampled = chain_with(o, 0.1);
    CHECK(oversampled.stability().sub_steps == 4);
    CHECK(oversampled.stability().message.find("4 sub-steps for accuracy") != std::string::npos);
    o.integrator = Integrator::trapezoidal;
    CHECK(chain_with(o, 0.1).stability().sub_steps == 1);
    // Stability needs more than asked: stability wins (omega_max T = 5 needs 3: (5 / 3)^2 / 4 = 0.69 < 0.9,
    // (5 / 2)^2 / 4 = 1.56).
    o.integrator = Integrator::explicit_verlet;
    o.stability.min_sub_steps = 2;
    const TransverseNetwork needs_more = chain_with(o, 5.0);
    CHECK(needs_more.stability().sub_steps == 3);
    CHECK(needs_more.stability().margin() < 0.9);
}
