// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/laned_network: N identical networks stepped as lanes give, lane by
// lane, the bits of N separate TransverseNetworks (laned_network.hpp, "Bit identity"), and the runtime
// guard stays per lane.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/cpu_features.hpp"
#include "engine/core/integrators/laned_network.hpp"
#include "test_bodies.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

namespace {

using ameoto::Integrator;
using ameoto::LanedNetwork;
using ameoto::NetworkOptions;
using ameoto::TransverseNetwork;

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// A 50-mass lattice membrane with Rayleigh damping (nylon-like: 0.06 kg/m^2, 1 kN/m, alpha 20 /s,
// beta 2e-6 s), finalized with the given integrator and at least min_sub_steps sub-steps.
TransverseNetwork prototype(Integrator integrator, int min_sub_steps) {
    TransverseNetwork net = ameoto::test::lattice_membrane(50, 0.06, 1000.0, 20.0, 2e-6).network;
    NetworkOptions o = ameoto::test::options_for(integrator);
    o.stability.min_sub_steps = min_sub_steps;
    net.finalize(kT, o);
    return net;
}

struct Comparison {
    long compared = 0, differing = 0;
    void check(double a, double b) {
        ++compared;
        if (bits(a) != bits(b)) ++differing;
    }
};

// Steps `lanes` and `count` copies of `proto` for `steps` samples with a pseudo-random schedule of forces
// on several lanes and masses (a few large, so the damping and every link act), comparing every net
// force, position and velocity bit for bit each sample, and the energies and finiteness every 64.
Comparison run_both(const TransverseNetwork& proto, int count, int ceiling, int steps) {
    LanedNetwork lanes;
    lanes.set_kernel_ceiling(ceiling);
    lanes.init(proto, count);
    // The widest kernels the ceiling, the CPU and the padded lanes allow (AVX-512: a multiple of 8).
    const int expected = ceiling >= 64 && lanes.lanes() % 8 == 0 && ameoto::cpu_has_avx512f() ? 64
                         : ceiling >= 32 && ameoto::cpu_has_avx2()                              ? 32
                                                                                                : 16;
    CHECK(lanes.kernel_width() == expected);
    std::vector<TransverseNetwork> reference(static_cast<std::size_t>(count), proto);
    std::vector<double> forces(static_cast<std::size_t>(count));
    const int n = proto.mass_count();
    std::uint64_t state = 12345;
    auto next = [&state] {   // xorshift64: the schedule only needs to be varied and repeatable
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return state;
    };
    Comparison c;
    for (int s = 0; s < steps; ++s) {
        for (int hits = static_cast<int>(next() % 3); hits > 0; --hits) {
            const int lane = static_cast<int>(next() % static_cast<std::uint64_t>(count));
            const int mass = static_cast<int>(next() % static_cast<std::uint64_t>(n));
            const double f = (static_cast<double>(next() % 2001) - 1000.0) * 1e-3;
            lanes.apply_force(lane, mass, f);
            reference[static_cast<std::size_t>(lane)].apply_force(mass, f);
        }
        lanes.step(forces.data());
        for (int k = 0; k < count; ++k) {
            TransverseNetwork& r = reference[static_cast<std::size_t>(k)];
            c.check(forces[static_cast<std::size_t>(k)], r.step());
            for (int i = 0; i < n; ++i) {
                c.check(lanes.position(k, i), r.position(i));
                c.check(lanes.velocity(k, i), r.velocity(i));
            }
            if (s % 64 == 0) {
                c.check(lanes.energy(k), r.kinetic_plus_potential_energy());
                c.check(lanes.guard_energy_limit(k), r.guard_energy_limit());
                CHECK(lanes.finite(k) == r.finite());
            }
        }
    }
    return c;
}

}  // namespace

TEST_CASE("laned network: every lane is bit-identical to its own TransverseNetwork") {
    // Explicit Verlet and symplectic Euler, one and three sub-steps, lane counts that fill the padded
    // width (8) and that do not (6, 7), the baseline (SSE2), AVX2 and AVX-512 kernels (where the CPU has
    // them).
    for (Integrator integrator : {Integrator::explicit_verlet, Integrator::symplectic_euler}) {
        for (int sub_steps : {1, 3}) {
            const TransverseNetwork proto = prototype(integrator, sub_steps);
            REQUIRE(proto.stability().sub_steps == sub_steps);
            for (int count : {6, 7, 8}) {
                for (int ceiling : {16, 32, 64}) {
                    CAPTURE(std::string(ameoto::integrator_name(integrator)));
                    CAPTURE(sub_steps);
                    CAPTURE(count);
                    CAPTURE(ceiling);
                    const Comparison c = run_both(proto, count, ceiling, 2000);
                    CHECK(c.compared > 2000L * count * 2 * proto.mass_count());
                    CHECK(c.differing == 0);
                }
            }
        }
    }
}

TEST_CASE("laned network: generic lane counts (not 4, 8, 12, 16) and one lane are bit-identical too") {
    const TransverseNetwork proto = prototype(Integrator::explicit_verlet, 1);
    for (int count : {1, 3, 17, 21}) {
        CAPTURE(count);
        for (int ceiling : {32, 64}) {   // 17 and 21 pad to 20 and 24 lanes: AVX2, then AVX-512 for 24
            CAPTURE(ceiling);
            const Comparison c = run_both(proto, count, ceiling, 300);
            CHECK(c.differing == 0);
        }
    }
}

TEST_CASE("laned network: the layout is node-major with the lanes padded to a multiple of 4") {
    const TransverseNetwork proto = prototype(Integrator::explicit_verlet, 1);
    LanedNetwork lanes;
    lanes.init(proto, 7);
    CHECK(lanes.lanes() == 8);
    CHECK(lanes.count() == 7);
    CHECK(lanes.mass_count() == proto.mass_count());
    lanes.apply_force(5, 3, 1.0);
    std::vector<double> f(7);
    lanes.step(f.data());
    lanes.step(f.data());
    const double* x = lanes.positions();
    CHECK(x[3 * 8 + 5] == lanes.position(5, 3));
    CHECK(x[3 * 8 + 5] != 0.0);
    std::vector<double> all(static_cast<std::size_t>(8 * proto.mass_count())), one(static_cast<std::size_t>(proto.mass_count()));
    lanes.velocities(all.data());
    lanes.velocities(5, one.data());
    for (int i = 0; i < proto.mass_count(); ++i) {
        CHECK(bits(all[static_cast<std::size_t>(i * 8 + 5)]) == bits(one[static_cast<std::size_t>(i)]));
        CHECK(all[static_cast<std::size_t>(i * 8 + 7)] == 0.0);   // the padding lane stays at rest
        CHECK(all[static_cast<std::size_t>(i * 8 + 4)] == 0.0);   // an unforced lane too
    }
}

TEST_CASE("laned network: the runtime guard resets only the lane that went non-finite, and counts it") {
    for (bool every_step : {false, true}) {
        CAPTURE(every_step);
        TransverseNetwork net = ameoto::test::lattice_membrane(50, 0.06, 1000.0, 20.0, 2e-6).network;
        NetworkOptions o;
        if (every_step) o.guard.check_every_steps = 1;   // step() guards itself, as TransverseNetwork does
        net.finalize(kT, o);
        LanedNetwork lanes;
        lanes.init(net, 6);
        std::vector<double> f(6);
        lanes.apply_force(1, 10, 0.5);
        lanes.apply_force(2, 10, std::numeric_limits<double>::infinity());
        lanes.step(f.data());
        if (!every_step) {
            lanes.step(f.data());
            CHECK_FALSE(lanes.finite(2));
            CHECK(lanes.guard(2));
        } else {
            CHECK(f[2] == 0.0);   // the reset panel's net force is dropped, as TransverseNetwork::step does
        }
        CHECK(lanes.guard_resets(2) == 1);
        CHECK(lanes.finite(2));
        CHECK(lanes.position(2, 10) == 0.0);
        for (int k : {0, 1, 3, 4, 5}) {
            CAPTURE(k);
            CHECK(lanes.finite(k));
            CHECK(lanes.guard_resets(k) == 0);
            CHECK_FALSE(lanes.guard(k));
        }
        CHECK(lanes.position(1, 10) != 0.0);   // the driven neighbour kept its motion
    }
}

TEST_CASE("laned network: refuses the implicit and modal integrators") {
    TransverseNetwork net = ameoto::test::lattice_membrane(20).network;
    net.finalize(kT, ameoto::test::options_for(Integrator::trapezoidal));
    LanedNetwork lanes;
    CHECK_THROWS_AS(lanes.init(net, 4), std::invalid_argument);
    CHECK_FALSE(LanedNetwork::supports(Integrator::modal));
    CHECK(LanedNetwork::supports(Integrator::symplectic_euler));
}
