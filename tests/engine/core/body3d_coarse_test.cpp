// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for Body3D's coarse steps (engine/core/body3d.hpp, "Coarse steps"; engine/core/body3d_coarse.cpp):
// which multiple coarse_factor() allows, that step(k) gives the same bits on the AVX2 and the scalar
// step, and what a coarse step changes in a trajectory.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/lattice_ball.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/water_drop_body.hpp"

using namespace ameoto::test::common;

using ameoto::Body3D;
using ameoto::Integrator;
using ameoto::Vec3;

namespace {

constexpr double kBurst = 8.0;   // m/s, the burst's outward speed

// A 5 mm water drop as body3d_test.cpp's shattering drop (122 masses, 537 cohesive links with the
// calibration of engine/models/drop.hpp), at terminal speed.
Body3D water_drop(bool portable) {
    Body3D body;
    ameoto::test::add_five_mm_water_drop(body, Vec3{0.3, 0.0, -9.09});
    body.set_gravity(Vec3{0.0, 0.0, -9.80665});
    body.set_integrator(Integrator::symplectic_euler);
    body.set_portable_kernels(portable);
    body.finalize(kT);
    return body;
}

// The same drop bursting in the air, as a splash's crown does: every mass flung out from the centre
// at `speed` and up at 2 m/s. Its links tear; it flies apart into single masses, pairs and triples.
Body3D burst(bool portable, double speed) {
    Body3D body = water_drop(portable);
    Vec3 centre{};
    for (int i = 0; i < body.mass_count(); ++i) centre = centre + body.position(i);
    centre = centre / body.mass_count();
    for (int i = 0; i < body.mass_count(); ++i) {
        const Vec3 r = body.position(i) - centre;
        const double length = ameoto::norm(r);
        body.set_velocity(i, Vec3{0.0, 0.0, 2.0} + (length > 0.0 ? (speed / length) * r : Vec3{}));
    }
    return body;
}

bool same_state(const Body3D& x, const Body3D& y) {
    for (int i = 0; i < x.mass_count(); ++i) {
        const Vec3 p = x.position(i), q = y.position(i), v = x.velocity(i), w = y.velocity(i);
        if (p.x != q.x || p.y != q.y || p.z != q.z || v.x != w.x || v.y != w.y || v.z != w.z) return false;
    }
    for (int l = 0; l < x.link_count(); ++l)
        if (x.link_broken(l) != y.link_broken(l)) return false;
    return x.lowest_z() == y.lowest_z();
}

}  // namespace

TEST_CASE("body3d coarse: a lone mass under gravity and drag: step(k) is symplectic Euler with the step k T") {
    // One mass, no links: coarse_factor() is limited only by drag (its gamma bound) and the multiple
    // asked for. step(4) must give exactly v += 4T F / m, x += 4T v, the scheme with a 4 times longer
    // step; and four ordinary steps differ from it by the scheme's own O(T) error.
    auto lone = [] {
        Body3D body;
        const int m = body.add_mass(5.354e-7, Vec3{0.0, 0.0, 0.1});
        body.set_velocity(m, Vec3{1.0, 0.5, 4.0});
        body.set_quadratic_drag(m, 6.36e-8);
        body.set_gravity(Vec3{0.0, 0.0, -9.80665});
        body.set_integrator(Integrator::symplectic_euler);
        body.finalize(kT);
        return body;
    };
    Body3D coarse = lone(), fine = lone();
    coarse.step();   // lowest_z() known from here on
    fine.step();
    CHECK(coarse.coarse_factor(4, 0.0) == 4);
    CHECK(coarse.coarse_factor(64, 0.0) == 64);   // nothing stiff: only the limit asked for
    // The expected coarse step, written out (Body3D's forces(): F = m g - (c + b |v|) v).
    const Vec3 v0 = coarse.velocity(0), x0 = coarse.position(0);
    const double m = coarse.mass(0), b = coarse.quadratic_drag(0), big = 4.0 * kT;
    const double drag = 0.0 + b * std::sqrt(v0.x * v0.x + v0.y * v0.y + v0.z * v0.z);
    const Vec3 f{0.0 + m * 0.0 - drag * v0.x, 0.0 + m * 0.0 - drag * v0.y, 0.0 + m * -9.80665 - drag * v0.z};
    const double inv_m = 1.0 / m;
    const Vec3 v1{v0.x + big * f.x * inv_m, v0.y + big * f.y * inv_m, v0.z + big * f.z * inv_m};
    const Vec3 x1{x0.x + big * v1.x, x0.y + big * v1.y, x0.z + big * v1.z};
    REQUIRE(coarse.step(4));
    for (int k = 0; k < 4; ++k) fine.step();
    CHECK(coarse.velocity(0).x == v1.x);
    CHECK(coarse.velocity(0).y == v1.y);
    CHECK(coarse.velocity(0).z == v1.z);
    CHECK(coarse.position(0).x == x1.x);
    CHECK(coarse.position(0).y == x1.y);
    CHECK(coarse.position(0).z == x1.z);
    // 0.1 s of flight, coarse (k = 4) against fine: symplectic Euler's global error is about g t k T / 2
    // in position (0.1 s x 9.8 m/s^2 x 83 us / 2 = 41 um for 4 T, a quarter of it for T); the drag
    // time constant (m / (b |v|), 2 s here) adds less.
    for (int n = 0; n < 1200; ++n) {
        REQUIRE(coarse.step(4));
        for (int k = 0; k < 4; ++k) fine.step();
    }
    const Vec3 dx = coarse.position(0) - fine.position(0);
    MESSAGE("after 0.1 s: coarse - fine = " << dx.x * 1e6 << ", " << dx.y * 1e6 << ", " << dx.z * 1e6 << " um");
    CHECK(std::fabs(dx.z) < 50e-6);
    CHECK(std::fabs(dx.z) > 1e-6);   // a different scheme step: not the same trajectory
    CHECK(std::fabs(dx.x) < 5e-6);
}

TEST_CASE("body3d coarse: the multiple allowed: the stiffest piece, the floor, and the cases with none") {
    // Two masses joined by a spring with omega T = 0.5 (exact: 2k/m, body3d_test.cpp): (w k T)^2 / 4 < 0.9
    // up to w k T < 1.897, so k = 3 (1.5) is the largest; a third mass on a chain raises the
    // Gershgorin bound to 4k/m (omega T = 0.707 on it): k = 2.
    const double m = 1e-6, spring = m * std::pow(0.5 / kT, 2) / 2.0;
    auto chain = [&](int masses) {
        Body3D body;
        for (int i = 0; i < masses; ++i) body.add_mass(m, Vec3{1e-3 * i, 0.0, 1.0});
        for (int i = 0; i + 1 < masses; ++i) body.add_spring(i, i + 1, spring, 0.0, 1e-3);
        body.set_integrator(Integrator::symplectic_euler);
        body.finalize(kT);
        body.step();
        return body;
    };
    Body3D pair = chain(2), triple = chain(3);
    CHECK(pair.coarse_factor(8, 0.0) == 3);
    CHECK(triple.coarse_factor(8, 0.0) == 2);
    CHECK(pair.coarse_factor(2, 0.0) == 2);   // never more than asked
    CHECK(pair.coarse_factor(1, 0.0) == 1);
    // The floor: at rest 1 m up, a step of k T travels at most (1.5 x 0 + 1 m/s + g k T) k T, far less
    // than 1 m; with the floor just under the masses, not even one coarse step fits.
    CHECK(pair.coarse_factor(8, 1.0 - 1e-3) == 3);
    CHECK(pair.coarse_factor(8, 1.0 - 1e-6) == 1);
    CHECK(pair.coarse_factor(8, 1.5) == 1);
    // An external force for the step to come: that step is an ordinary one.
    pair.apply_force(0, Vec3{0.0, 0.0, 1e-9});
    CHECK(pair.coarse_factor(8, 0.0) == 1);
    pair.step();
    CHECK(pair.coarse_factor(8, 0.0) == 3);
    // Unknown lowest mass (moved by hand, reset): none until the next step.
    pair.set_position(0, Vec3{0.0, 0.0, 1.0});
    CHECK(pair.coarse_factor(8, 0.0) == 1);
    pair.step();
    CHECK(pair.coarse_factor(8, 0.0) == 3);
    pair.reset();
    CHECK(pair.coarse_factor(8, 0.0) == 1);
    // CORDIS keeps x[n-1]: never coarse; its step(k) is k ordinary steps.
    Body3D cordis = chain(2), ordinary = chain(2);
    cordis.set_integrator(Integrator::explicit_verlet);
    ordinary.set_integrator(Integrator::explicit_verlet);
    CHECK(cordis.coarse_factor(8, 0.0) == 1);
    cordis.step(3);
    for (int k = 0; k < 3; ++k) ordinary.step();
    CHECK(cordis.position(1).x == ordinary.position(1).x);
    CHECK(cordis.position(1).z == ordinary.position(1).z);
}

TEST_CASE("body3d coarse: a splash in the air takes coarse steps, the same bits on the AVX2 and the scalar step") {
    // burst(): the drop flying apart in the air. Each step both bodies ask coarse_factor(4, floor) and
    // take what it allows; they must agree on it and on every mass, link and lowest_z() after every
    // step, and much of the 0.1 s must be coarse.
    Body3D fast = burst(false, kBurst), portable = burst(true, kBurst);
    CHECK_FALSE(portable.avx2_kernels());
    if (!fast.avx2_kernels()) MESSAGE("no AVX2 on this CPU: the scalar step against itself");
    long coarse_steps = 0, covered = 0;
    int first_difference = -1;
    for (int n = 0; n < 4800 && first_difference < 0;) {
        const int k = fast.coarse_factor(4, -1e3);
        if (portable.coarse_factor(4, -1e3) != k) first_difference = n;
        fast.step(k);
        portable.step(k);
        if (!same_state(fast, portable)) first_difference = n;
        if (k > 1) {
            ++coarse_steps;
            covered += k;
        }
        n += k;
    }
    MESSAGE(coarse_steps << " coarse steps covering " << covered << " of 4800 samples; " << fast.broken_link_count()
                         << " of " << fast.link_count() << " links broken");
    CHECK(first_difference == -1);
    CHECK(covered > 2400);
    CHECK(fast.resets() == 0);
    CHECK(portable.resets() == 0);
}

TEST_CASE("body3d coarse: coarse_factor() and step(k) never allocate or lock") {
    Body3D body = burst(false, kBurst);
    ameoto::test::RtAudit audit;
    long coarse = 0;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int n = 0; n < 2000; ++n) {
            const int k = body.coarse_factor(4, -1e3);
            coarse += k > 1 ? 1 : 0;
            body.step(k);
        }
    }
    CHECK(coarse > 0);
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
}
