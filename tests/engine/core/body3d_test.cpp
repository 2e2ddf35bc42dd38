// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/body3d: the 3-D mass-interaction body (links, drag, integrators, stability, guard).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/lattice_ball.hpp"
#include "engine/core/random.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/water_drop_body.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using ameoto::Body3D;
using ameoto::Integrator;
using ameoto::LinkKind;
using ameoto::Vec3;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Force on mass a after one symplectic-Euler step from the current state: m (v1 - v0) / T (the
// scheme's v += T F / m, inverted; rounding only).
Vec3 force_seen(Body3D& body, int a) {
    const Vec3 v0 = body.velocity(a);
    body.step();
    return (body.mass(a) / body.sub_step_time()) * (body.velocity(a) - v0);
}

// A 5 mm lattice drop (about 125 masses, 12 neighbours each) whose links are breakable springs,
// with contact links over a third of the neighbour pairs: all three link kinds at once.
ameoto::LatticeBall mixed_ball(double stiffness, double damping, double break_force) {
    ameoto::LatticeBallSpec spec;
    spec.diameter = 5e-3;
    spec.link_kind = LinkKind::breakable;
    spec.stiffness = stiffness;
    spec.damping = damping;
    spec.break_force = break_force;
    auto ball = ameoto::make_lattice_ball(spec);
    for (int l = 0; l < ball.info.link_count; l += 3)
        ball.body.add_contact(ball.body.link_a(l), ball.body.link_b(l), stiffness, damping, ball.info.spacing);
    return ball;
}

void randomise_velocities(Body3D& body, std::uint64_t seed, Vec3 drift, double spread) {
    ameoto::Random rng(seed);
    for (int i = 0; i < body.mass_count(); ++i)
        body.set_velocity(i, drift + Vec3{rng.uniform(-spread, spread), rng.uniform(-spread, spread), rng.uniform(-spread, spread)});
}

}  // namespace

TEST_CASE("body3d: a spring acts along its axis with -k (L - l0)") {
    // Two masses on an oblique axis, 3 mm apart, rest length 2 mm: stretched by 1 mm.
    const double m = 2e-6, k = 40.0, l0 = 2e-3;
    const Vec3 axis = Vec3{1.0, -2.0, 2.0} / 3.0;   // unit vector
    for (double length : {3e-3, 1.5e-3}) {          // stretched, then compressed
        CAPTURE(length);
        Body3D body;
        const int a = body.add_mass(m, length * axis);
        const int b = body.add_mass(3.0 * m, Vec3{});
        body.add_spring(a, b, k, 0.0, l0);
        body.set_integrator(Integrator::symplectic_euler);
        body.finalize(kT);
        const Vec3 f = force_seen(body, a);
        const Vec3 expected = (-k * (length - l0)) * axis;   // F1 = -k (L - l0) u
        CHECK(ameoto::norm(f - expected) < 1e-9 * ameoto::norm(expected));
        // Newton's third law: b received the opposite impulse.
        const Vec3 fb = (body.mass(b) / kT) * body.velocity(b);
        CHECK(ameoto::norm(fb + expected) < 1e-9 * ameoto::norm(expected));
    }
}

TEST_CASE("body3d: a link's damper resists axial relative speed only") {
    const double m = 1e-6, z = 3e-4, l0 = 1e-3;
    Body3D body;
    const int a = body.add_mass(m, Vec3{l0, 0.0, 0.0});
    const int b = body.add_mass(m, Vec3{});
    body.add_spring(a, b, 10.0, z, l0);   // at rest length: only the damper can act
    body.set_integrator(Integrator::symplectic_euler);
    SUBCASE("across the axis: no force") {
        body.set_velocity(a, Vec3{0.0, 0.2, -0.1});
        body.finalize(kT);
        const Vec3 f = force_seen(body, a);
        CHECK(ameoto::norm(f) == 0.0);
    }
    SUBCASE("along the axis: -z (v1 - v2) . u") {
        body.set_velocity(a, Vec3{0.3, 0.2, 0.0});
        body.finalize(kT);
        const Vec3 f = force_seen(body, a);
        CHECK(f.x == ameoto::test::relative(-z * 0.3).epsilon(1e-9));
        CHECK(std::abs(f.y) < 1e-12 * z);
        CHECK(f.z == 0.0);
    }
}

TEST_CASE("body3d: a contact link pushes only while compressed, and never pulls") {
    const double m = 1e-6, k = 50.0, z = 1e-3, l0 = 1e-3;
    auto run = [&](double gap, double approach_speed) {
        Body3D body;
        const int a = body.add_mass(m, Vec3{0.0, 0.0, gap});
        const int b = body.add_mass(m, Vec3{});
        body.add_contact(a, b, k, z, l0);
        body.set_integrator(Integrator::symplectic_euler);
        body.set_velocity(a, Vec3{0.0, 0.0, -approach_speed});
        body.finalize(kT);
        return force_seen(body, a).z;
    };
    CHECK(run(1.5e-3, 0.0) == 0.0);                                              // apart: nothing
    CHECK(run(1.5e-3, 0.5) == 0.0);                                              // approaching, not touching
    CHECK(run(0.8e-3, 0.0) == ameoto::test::relative(k * 0.2e-3).epsilon(1e-9));        // compressed: pushes
    CHECK(run(0.8e-3, 0.5) == ameoto::test::relative(k * 0.2e-3 + z * 0.5).epsilon(1e-9));   // and damps the approach
    // Compressed but separating fast: spring 0.01 N, damper -0.05 N; a penalty damper would pull. It is clipped.
    CHECK(run(0.8e-3, -50.0) == 0.0);
}

TEST_CASE("body3d: a breakable link breaks at its threshold, reports it once, and is skipped") {
    // Two 0.1 g masses held by a spring and a breakable link in parallel, pulled apart at 2 m/s: the
    // pair's relative mode (omega^2 = 2 (2k) / m) swings 1 mm, and the weak link breaks at 0.5 mm.
    const double m = 1e-4, k = 100.0, l0 = 1e-3, threshold = 0.05, speed = 2.0;
    Body3D body;
    const int a = body.add_mass(m, Vec3{l0, 0.0, 0.0});
    const int b = body.add_mass(m, Vec3{});
    const int spring = body.add_spring(a, b, k, 0.0, l0);
    const int weak = body.add_breakable(a, b, k, 0.0, l0, threshold);
    body.set_integrator(Integrator::symplectic_euler);
    body.set_velocity(a, Vec3{speed, 0.0, 0.0});
    body.finalize(kT);
    int step_of_break = -1;
    for (int n = 0; n < 2000 && step_of_break < 0; ++n) {
        body.step();
        if (!body.breaks().empty()) step_of_break = n;
    }
    REQUIRE(step_of_break >= 0);
    REQUIRE(body.breaks().size() == 1);
    const auto e = body.breaks()[0];
    CHECK(e.link == weak);
    CHECK(e.a == a);
    CHECK(e.b == b);
    CHECK(e.force < -threshold);   // a pull (negative: towards each other) past the threshold...
    // ...caught in the sub-step it crossed: the force moves by at most k * (relative speed) * T per step.
    CHECK(e.force > -(threshold + k * speed * kT));
    CHECK(e.sub_step == 0);
    CHECK(body.link_broken(weak));
    CHECK_FALSE(body.link_broken(spring));
    CHECK(body.broken_link_count() == 1);
    CHECK_FALSE(body.link_bonds(weak));
    CHECK(body.link_bonds(spring));
    // The list is per step: the next step reports nothing, and the broken link stores no energy.
    body.step();
    CHECK(body.breaks().empty());
    const double stretch = ameoto::norm(body.position(a) - body.position(b)) - l0;
    CHECK(body.elastic_energy() == ameoto::test::relative(0.5 * k * stretch * stretch).epsilon(1e-12));
    // reset() mends it.
    body.reset();
    CHECK_FALSE(body.link_broken(weak));
    CHECK(body.broken_link_count() == 0);
}

TEST_CASE("body3d: a cohesive link breaks under tension only, and its core pushes before and after") {
    // A liquid's bond (engine/models/drop.hpp): k = 0.1 N/m, rest 1 mm, threshold 1e-4 N (a stretch
    // of 1 mm), core below 0.9 mm with 100 N/m.
    const double m = 5e-7, k = 0.1, z = 1e-5, l0 = 1e-3, threshold = 1e-4, lc = 0.9e-3, kc = 100.0;
    auto pair = [&](double length, double speed_apart) {
        Body3D body;
        const int a = body.add_mass(m, Vec3{length, 0.0, 0.0});
        const int b = body.add_mass(m, Vec3{});
        body.add_cohesive(a, b, k, z, l0, threshold, lc, kc);
        body.set_integrator(Integrator::symplectic_euler);
        body.set_velocity(a, Vec3{speed_apart, 0.0, 0.0});
        body.finalize(kT);
        return body;
    };
    SUBCASE("bonded, between core and break: the spring-damper") {
        Body3D body = pair(1.5e-3, 0.2);
        const Vec3 f = force_seen(body, 0);
        CHECK(f.x == ameoto::test::relative(-k * 0.5e-3 - z * 0.2).epsilon(1e-9));
        CHECK(body.breaks().empty());
    }
    SUBCASE("inside the core: spring plus core push") {
        Body3D body = pair(0.8e-3, 0.0);
        CHECK(body.elastic_energy() == ameoto::test::relative(0.5 * k * 0.2e-3 * 0.2e-3 + 0.5 * kc * 0.1e-3 * 0.1e-3).epsilon(1e-9));
        CHECK(force_seen(body, 0).x == ameoto::test::relative(k * 0.2e-3 + kc * 0.1e-3).epsilon(1e-9));
    }
    SUBCASE("compressed far past the threshold: pushes, never breaks") {
        Body3D body = pair(0.2e-3, -1.0);   // core force 0.07 N, 700 times the threshold
        body.step();
        CHECK(body.breaks().empty());
        CHECK(body.broken_link_count() == 0);
    }
    SUBCASE("the damper does not tear: stretched just below the threshold, pulled apart fast") {
        Body3D body = pair(1.99e-3, 50.0);   // damper 5e-4 N, spring 0.99e-4 N
        REQUIRE(body.stability().sub_steps == 1);
        body.step();   // the spring crosses 1e-4 N during this step: breaks in the next
        CHECK(body.breaks().empty());
        body.step();
        REQUIRE(body.breaks().size() == 1);
        CHECK(body.breaks()[0].force < -threshold);   // the spring's pull
        CHECK(body.breaks()[0].force > -threshold - k * 50.0 * kT);
        CHECK_FALSE(body.link_bonds(0));
    }
    SUBCASE("broken: only the core, which pushes when they collide again") {
        Body3D body = pair(2.5e-3, 0.0);   // past the threshold at once
        body.step();
        REQUIRE(body.broken_link_count() == 1);
        body.set_position(0, Vec3{0.85e-3, 0.0, 0.0});
        body.set_velocity(0, Vec3{});
        body.set_velocity(1, Vec3{});
        CHECK(force_seen(body, 0).x == ameoto::test::relative(kc * 0.05e-3).epsilon(1e-9));   // no spring
        body.set_position(0, Vec3{1.2e-3, 0.0, 0.0});
        body.set_velocity(0, Vec3{});
        body.set_velocity(1, Vec3{});
        CHECK(force_seen(body, 0).x == 0.0);   // apart: nothing holds them
        CHECK(body.elastic_energy() == 0.0);
    }
}

TEST_CASE("body3d: uniform cohesive links (a drop) take a faster pass with the same result to the bit") {
    // The same lattice twice; the second body also holds a spring between two far-away masses, so
    // its links are not uniform and it runs the generic pass.
    auto build = [](bool generic) {
        Body3D body;
        const auto shape = ameoto::lattice_ball_shape(64);
        for (const Vec3& p : shape.position) body.add_mass(5e-7, 4e-3 * p);
        const double h = 4e-3 * shape.spacing;
        for (int l = 0; l < shape.link_count(); ++l)
            body.add_cohesive(shape.link_a[static_cast<std::size_t>(l)], shape.link_b[static_cast<std::size_t>(l)], 0.15, 1e-5, h,
                              4e-5, 0.9 * h, 140.0);
        if (generic) {
            const int a = body.add_mass(1e-6, Vec3{1.0, 0.0, 0.0});
            const int b = body.add_mass(1e-6, Vec3{1.001, 0.0, 0.0});
            body.add_spring(a, b, 1.0, 0.0, 1e-3);
        }
        body.set_gravity(Vec3{0.0, 0.0, -9.8});
        body.set_integrator(Integrator::symplectic_euler);
        randomise_velocities(body, 11, Vec3{0.0, 0.0, -3.0}, 0.3);   // enough to break some bonds
        body.finalize(kT);
        return body;
    };
    Body3D fast = build(false), generic = build(true);
    REQUIRE(fast.stability().sub_steps == generic.stability().sub_steps);
    for (int n = 0; n < 300; ++n) {
        fast.step();
        generic.step();
    }
    CHECK(fast.broken_link_count() > 0);
    CHECK(fast.broken_link_count() == generic.broken_link_count());
    int differing = 0;
    for (int i = 0; i < fast.mass_count(); ++i) {
        const Vec3 p = fast.position(i), q = generic.position(i), v = fast.velocity(i), w = generic.velocity(i);
        differing += (p.x != q.x || p.y != q.y || p.z != q.z || v.x != w.x || v.y != w.y || v.z != w.z) ? 1 : 0;
    }
    CHECK(differing == 0);
}

TEST_CASE("body3d: a drop that shatters on a floor gives the same bits in every pass and build") {
    // A 5 mm water drop (122 masses, 537 cohesive links, the calibration of engine/models/drop.hpp) at
    // terminal speed onto a rigid floor (test only, as in drop_test.cpp): its links go from all bonded
    // (the dense uniform pass) to mostly broken (the sparse one), with cores, breaks and touching broken
    // neighbours on the way, and a mass moved by set_position(). Three bodies: the uniform pass on the
    // step finalize() picks (AVX2 where the CPU has it), the same forced to the scalar step, and the
    // generic pass (a far-away extra spring makes the links non-uniform; on AVX2 its per-mass kernels are
    // the vector ones). Every step their states and break events must agree to the bit.
    auto build = [](bool generic, bool portable, Integrator scheme) {
        Body3D body;
        ameoto::test::add_five_mm_water_drop(body, Vec3{0.3, 0.0, -9.09});
        if (generic) {
            const int a = body.add_mass(1e-6, Vec3{1.0, 0.0, 0.0});
            const int b = body.add_mass(1e-6, Vec3{1.001, 0.0, 0.0});
            body.add_spring(a, b, 1.0, 0.0, 1e-3);
        }
        body.set_gravity(Vec3{0.0, 0.0, -9.80665});
        body.set_integrator(scheme);
        body.set_portable_kernels(portable);
        body.finalize(kT);
        return body;
    };
    // The floor: each mass below z = 0 is pushed up by a critically damped penalty, never pulled.
    auto floor = [](Body3D& body, int masses) {
        for (int i = 0; i < masses; ++i) {
            const Vec3 p = body.position(i);
            if (p.z >= 0.0) continue;
            const double m = body.mass(i), omega = 2e4;
            const double push = m * omega * omega * (-p.z) - 2.0 * m * omega * body.velocity(i).z;
            body.apply_force(i, Vec3{0.0, 0.0, std::max(0.0, push)});
        }
    };
    auto same = [](const Body3D& x, const Body3D& y) {
        for (int i = 0; i < x.mass_count() && i < y.mass_count(); ++i) {
            const Vec3 p = x.position(i), q = y.position(i), v = x.velocity(i), w = y.velocity(i);
            if (p.x != q.x || p.y != q.y || p.z != q.z || v.x != w.x || v.y != w.y || v.z != w.z) return false;
        }
        for (int l = 0; l < x.link_count() && l < y.link_count(); ++l)
            if (x.link_broken(l) != y.link_broken(l)) return false;
        if (x.breaks().size() != y.breaks().size()) return false;
        for (std::size_t e = 0; e < x.breaks().size(); ++e) {
            const auto &a = x.breaks()[e], &b = y.breaks()[e];
            if (a.link != b.link || a.a != b.a || a.b != b.b || a.force != b.force || a.sub_step != b.sub_step)
                return false;
        }
        return true;
    };
    for (auto scheme : {Integrator::symplectic_euler, Integrator::explicit_verlet}) {
        CAPTURE(static_cast<int>(scheme));
        Body3D fast = build(false, false, scheme);
        Body3D portable = build(false, true, scheme);
        Body3D generic = build(true, false, scheme);
        CHECK_FALSE(portable.avx2_kernels());
        if (!fast.avx2_kernels()) MESSAGE("no AVX2 on this CPU: only the scalar step is compared");
        const int masses = fast.mass_count();
        int first_difference = -1, most_broken_at = -1;
        for (int n = 0; n < 1500 && first_difference < 0; ++n) {
            if (n == 1000) {
                // Put a mass beside the far end of a broken link, inside its core: the state edit must
                // not let a pass miss the link (the sparse pass lists its links again).
                int far = -1;
                for (int l = 0; l < fast.link_count() && far < 0; ++l) {
                    const double length = ameoto::norm(fast.position(fast.link_a(l)) - fast.position(fast.link_b(l)));
                    if (fast.link_broken(l) && length > 0.02) far = l;
                }
                REQUIRE(far >= 0);
                for (Body3D* b : {&fast, &portable, &generic})
                    b->set_position(b->link_a(far), b->position(b->link_b(far)) + Vec3{0.0, 2e-4, 0.0});
            }
            for (Body3D* b : {&fast, &portable, &generic}) {
                floor(*b, masses);
                b->step();
            }
            if (!same(fast, portable) || !same(fast, generic)) first_difference = n;
            // lowest_z() (the broad phase's bound, measured by the update): the lowest position, on both steps.
            double lowest = std::numeric_limits<double>::infinity();
            for (int i = 0; i < masses; ++i) lowest = std::min(lowest, fast.position(i).z);
            if (fast.lowest_z() != lowest || portable.lowest_z() != lowest) first_difference = n;
            if (most_broken_at < 0 && 4 * fast.broken_link_count() > 3 * fast.link_count()) most_broken_at = n;
        }
        CHECK(first_difference == -1);
        CHECK(most_broken_at > 0);   // the sparse pass ran (measured: from step 62 on)
        CHECK(fast.resets() == 0);
        // Unknown (skip nothing) once a mass is moved by hand, until the next step.
        fast.set_position(0, fast.position(0));
        CHECK(fast.lowest_z() == -std::numeric_limits<double>::infinity());
        fast.step();
        CHECK(std::isfinite(fast.lowest_z()));
        fast.reset();
        CHECK(fast.lowest_z() == -std::numeric_limits<double>::infinity());
    }
}

TEST_CASE("body3d: a cohesive core counts in the stability bound") {
    Body3D body;
    const int a = body.add_mass(1e-6, Vec3{1e-3, 0.0, 0.0});
    const int b = body.add_mass(1e-6, Vec3{});
    body.add_cohesive(a, b, 1.0, 0.0, 1e-3, 1.0, 0.9e-3, 99.0);
    const auto& s = body.finalize(kT);
    CHECK(s.omega_max_bound == doctest::Approx(std::sqrt(2.0 * 100.0 / 1e-6)).epsilon(1e-12));
}

TEST_CASE("body3d: reserve(), clear() and re-building within capacity never allocate") {
    ameoto::LatticeBallSpec spec;
    spec.diameter = 3e-3;
    spec.stiffness = 0.2;
    Body3D body;
    body.reserve(64, 512);
    body.set_gravity(Vec3{0.0, 0.0, -9.8});
    body.set_integrator(Integrator::symplectic_euler);
    const auto shape = ameoto::lattice_ball_shape(27);
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int round = 0; round < 3; ++round) {
            body.clear();
            for (const Vec3& p : shape.position) body.add_mass(1e-6, 3e-3 * p);
            for (int l = 0; l < shape.link_count(); ++l)
                body.add_cohesive(shape.link_a[static_cast<std::size_t>(l)], shape.link_b[static_cast<std::size_t>(l)], 0.2,
                                  1e-6, 3e-3 * shape.spacing, 1e-4, 2.7e-3 * shape.spacing, 50.0);
            body.finalize(kT);
            for (int n = 0; n < 10; ++n) body.step();
        }
    }
    CHECK(body.mass_count() == 28);
    CHECK(body.link_count() == shape.link_count());
    CHECK(body.resets() == 0);
    CHECK(body.integrator() == Integrator::symplectic_euler);   // settings survive clear()
    CHECK(body.centre_of_mass().z < 0.0);                        // gravity too
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    (void)spec;
}

TEST_CASE("body3d: gravity, linear drag and quadratic drag follow their laws") {
    const double m = 5e-7;
    SUBCASE("free fall: v = g t (both schemes, exact for constant force)") {
        for (auto scheme : {Integrator::explicit_verlet, Integrator::symplectic_euler}) {
            Body3D body;
            const int a = body.add_mass(m, Vec3{});
            body.set_gravity(Vec3{0.0, 0.0, -9.80665});
            body.set_integrator(scheme);
            body.finalize(kT);
            for (int n = 0; n < 4800; ++n) body.step();
            CHECK(body.velocity(a).z == ameoto::test::relative(-9.80665 * 0.1).epsilon(1e-9));
            CHECK(body.velocity(a).x == 0.0);
        }
    }
    SUBCASE("linear drag -c v: v = v0 (1 - c T / m)^n") {
        const double c = 1e-5;   // c T / m = 4.2e-4 per step
        Body3D body;
        const int a = body.add_mass(m, Vec3{});
        body.set_linear_drag(a, c);
        body.set_integrator(Integrator::symplectic_euler);
        body.set_velocity(a, Vec3{3.0, 0.0, -4.0});
        body.finalize(kT);
        for (int n = 0; n < 4800; ++n) body.step();
        const double factor = std::pow(1.0 - c * kT / m, 4800);
        CHECK(body.velocity(a).x == doctest::Approx(3.0 * factor).epsilon(1e-9));
        CHECK(body.velocity(a).z == doctest::Approx(-4.0 * factor).epsilon(1e-9));
        // And the continuous law exp(-c t / m), to the scheme's first-order error c T / 2m = 2e-4 per unit time constant.
        CHECK(body.velocity(a).x == ameoto::test::relative(3.0 * std::exp(-c * 0.1 / m)).epsilon(1e-3));
    }
    SUBCASE("quadratic drag -b |v| v: v = v0 / (1 + b v0 t / m), direction kept") {
        const double b = 2e-7;   // about a 1 mm drop's
        Body3D body;
        const int a = body.add_mass(m, Vec3{});
        body.set_quadratic_drag(a, b);
        body.set_integrator(Integrator::symplectic_euler);
        body.set_velocity(a, Vec3{3.0, 0.0, -4.0});   // |v0| = 5 m/s
        body.finalize(kT);
        for (int n = 0; n < 48000; ++n) body.step();
        const Vec3 v = body.velocity(a);
        // Explicit scheme: first-order error b v T / 2m = 2e-5 relative per step's worth; 1e-3 over 1 s.
        CHECK(ameoto::norm(v) == ameoto::test::relative(5.0 / (1.0 + b * 5.0 * 1.0 / m)).epsilon(1e-3));
        CHECK(v.x / v.z == ameoto::test::relative(-0.75).epsilon(1e-12));
    }
}

TEST_CASE("body3d: fixed points never move and count once in the stability bound") {
    const double m = 1e-6, k = 20.0;
    Body3D body;
    const int f = body.add_fixed_point(Vec3{0.0, 0.0, 1e-3});
    const int a = body.add_mass(m, Vec3{});
    body.add_spring(f, a, k, 0.0, 2e-3);   // compressed: pushes a down, f not at all
    body.set_gravity(Vec3{0.0, 0.0, -9.8});
    body.set_velocity(f, Vec3{1.0, 1.0, 1.0});   // ignored for a fixed point
    body.apply_force(f, Vec3{1.0, 0.0, 0.0});    // likewise
    const auto& s = body.finalize(kT);
    // One mass on a link to a fixed point: omega^2 = k / m exactly (anchor-like, counted once).
    CHECK(s.omega_max_bound * s.omega_max_bound == ameoto::test::relative(k / m).epsilon(1e-12));
    for (int n = 0; n < 1000; ++n) body.step();
    CHECK(body.position(f).z == 1e-3);
    CHECK(body.position(f).x == 0.0);
    CHECK(ameoto::norm(body.velocity(f)) == 0.0);
    CHECK(body.mass(f) == 0.0);
    CHECK(body.is_fixed(f));
    CHECK(body.position(a).z < 0.0);
}

TEST_CASE("body3d: the two schemes give the same trajectory (to rounding)") {
    // body3d.hpp: symplectic Euler with v[n] = (x[n] - x[n-1]) / T is the CORDIS update, dampers,
    // drag and breaks included. Rounding differs (v stored vs differenced), and the mixed ball is
    // nonlinear, so compare over 2000 steps: positions agree to 1e-8 of the spacing (measured 2.6e-9:
    // 1e5 ulps of the 4 cm the drop has fallen, the nonlinearity amplifying the rounding).
    Body3D bodies[2] = {mixed_ball(12.5, 1e-5, 1.5e-4).body, mixed_ball(12.5, 1e-5, 1.5e-4).body};
    bodies[1].set_integrator(Integrator::symplectic_euler);
    double spacing = 0.0;
    for (auto& body : bodies) {
        randomise_velocities(body, 11, Vec3{0.0, 0.0, -1.0}, 0.1);
        body.set_gravity(Vec3{0.0, 0.0, -9.8});
        for (int i = 0; i < body.mass_count(); ++i) body.set_quadratic_drag(i, 1e-8);
        body.finalize(kT);
        spacing = body.rest_length(0);
    }
    int breaks[2] = {0, 0};
    for (int n = 0; n < 2000; ++n)
        for (int k = 0; k < 2; ++k) {
            bodies[k].step();
            breaks[k] += static_cast<int>(bodies[k].breaks().size());
        }
    double worst = 0.0;
    for (int i = 0; i < bodies[0].mass_count(); ++i)
        worst = std::max(worst, ameoto::norm(bodies[0].position(i) - bodies[1].position(i)));
    CHECK(worst < 1e-8 * spacing);
    CHECK(breaks[0] > 0);   // the comparison covered breaking links
    CHECK(breaks[0] == breaks[1]);
}

TEST_CASE("body3d: internal links conserve momentum (springs, dampers, contacts, breaks)") {
    // A free 5 mm lattice drop, about 125 masses, no gravity or drag, random velocities around a drift of
    // (0.05, -0.02, 0.03) m/s, links that break under the motion: over 10^4 steps the total momentum
    // must not change beyond rounding. Errors are relative to the momentum scale sum m |v|.
    for (auto scheme : {Integrator::explicit_verlet, Integrator::symplectic_euler}) {
        CAPTURE(static_cast<int>(scheme));
        auto ball = mixed_ball(12.5, 1e-5, 1.5e-4);
        Body3D& body = ball.body;
        body.set_integrator(scheme);
        randomise_velocities(body, 7, Vec3{0.05, -0.02, 0.03}, 0.1);
        REQUIRE(body.finalize(kT).sub_steps == 1);
        const Vec3 p0 = body.momentum();
        double scale = 0.0;
        for (int i = 0; i < body.mass_count(); ++i) scale += body.mass(i) * ameoto::norm(body.velocity(i));
        REQUIRE(ameoto::norm(p0) > 0.3 * scale);
        double worst = 0.0, rounding_bound = 0.0, worst_over_bound = 0.0;
        int breaks = 0;
        for (int n = 0; n < 10000; ++n) {
            body.step();
            breaks += static_cast<int>(body.breaks().size());
            // CORDIS rounding (as in transverse_network_test.cpp): each x[n+1] = 2x - x[n-1] + T^2 F/m is
            // rounded to ~1.5 ulp of |x|, and that error stays in v = (x[n] - x[n-1]) / T for good: bound it
            // by 2 eps m (|x| + |y| + |z|) / T per mass and step, plus the same again for reading v.
            double sum = 0.0;
            for (int i = 0; i < body.mass_count(); ++i) {
                const Vec3 p = body.position(i);
                sum += body.mass(i) * (std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
            }
            rounding_bound += 2.0 * kEps * sum / kT;
            const double error = ameoto::norm(body.momentum() - p0);
            worst = std::max(worst, error / scale);
            worst_over_bound = std::max(worst_over_bound, error / (rounding_bound + 2.0 * kEps * sum / kT));
        }
        CHECK(breaks > 50);   // links broke along the way (measured: 251)
        if (scheme == Integrator::symplectic_euler) {
            // v is state: only eps |v| per update is lost. Measured 1e-15; the brief's 1e-12 holds easily.
            CHECK(worst < 1e-13);
        } else {
            // CORDIS reads v from positions, so its momentum carries eps |x| / T per mass: the drop drifts
            // 1 cm in 10^4 steps, and 2.2e-16 * 1 cm * 48 kHz = 1e-13 m/s against |v| ~ 0.1 m/s is 1e-12
            // per mass already. 1e-12 relative is therefore the readout's own limit, not a leak (measured
            // 1.9e-12): assert the accumulated rounding bound, and 1e-11.
            CHECK(worst_over_bound <= 1.0);
            CHECK(worst < 1e-11);
        }
    }
}

TEST_CASE("body3d: stability report: Gershgorin bound and the fewest sub-steps") {
    SUBCASE("two free masses: the bound is the exact 2k/m of their relative mode") {
        const double m = 1e-6, k = m * std::pow(0.5 / kT, 2) / 2.0;   // omega T = 0.5
        Body3D body;
        body.add_spring(body.add_mass(m, Vec3{}), body.add_mass(m, Vec3{1e-3, 0.0, 0.0}), k, 0.0, 1e-3);
        const auto& s = body.finalize(kT);
        CHECK(s.omega_max_bound * kT == ameoto::test::relative(0.5).epsilon(1e-12));
        CHECK(s.sub_steps == 1);
        CHECK(s.stable());
    }
    SUBCASE("damping: link dampers, linear drag, quadratic drag at the speed bound") {
        const double m = 1e-6, z = 1e-4, c = 2e-5, b = 1e-7;
        Body3D body;
        const int a = body.add_mass(m, Vec3{}), f = body.add_fixed_point(Vec3{1e-3, 0.0, 0.0});
        body.add_spring(a, f, 0.0, z, 1e-3);
        body.set_linear_drag(a, c);
        body.set_quadratic_drag(a, b);
        body.set_speed_bound(10.0);
        const auto& s = body.finalize(kT);
        CHECK(s.gamma_max_bound == ameoto::test::relative((z + c + 2.0 * b * 10.0) / m).epsilon(1e-12));
        CHECK(s.margin() == ameoto::test::relative(2.0 * s.gamma_max_bound * kT / 4.0).epsilon(1e-12));
    }
    SUBCASE("a stiff lattice drop gets the fewest sub-steps with margin < 0.9") {
        ameoto::LatticeBallSpec spec;
        spec.diameter = 3e-3;
        auto ball = ameoto::make_lattice_ball(spec);
        // Gershgorin for an interior mass: 12 links, each counted twice: omega^2 = 24 k / m. Set omega T = 10.
        const double k = ball.info.node_mass * std::pow(10.0 / kT, 2) / 24.0;
        auto stiff = ameoto::make_lattice_ball({.diameter = 3e-3, .stiffness = k, .damping = 1e-6});
        const auto& s = stiff.body.finalize(kT);
        CHECK(s.omega_max_bound * kT == doctest::Approx(10.0).epsilon(1e-9));
        CHECK(s.margin() < 0.9);
        auto fewer = s;
        fewer.sub_steps -= 1;
        CHECK(fewer.margin() >= 0.9);
        CHECK(s.sub_steps == 6);   // 10 / 6 = 1.67 per sub-step: (1.67^2 + damping) / 4 = 0.70; 10/5 = 2 is out
    }
    SUBCASE("beyond 4096 sub-steps the body is refused") {
        Body3D body;
        const double m = 1e-6;
        body.add_spring(body.add_mass(m, Vec3{}), body.add_fixed_point(Vec3{1e-3, 0, 0}), m * std::pow(1e5 / kT, 2), 0.0, 1e-3);
        CHECK_THROWS_AS(body.finalize(kT), std::invalid_argument);
        CHECK_FALSE(body.finalize(kT, 1).stable());   // forcing is allowed; the report says it is unsafe
    }
}

TEST_CASE("body3d: a stiff body (omega_max T = 10) runs on sub-steps; forced to one step it diverges and the guard resets it") {
    ameoto::LatticeBallSpec spec;
    spec.diameter = 3e-3;
    spec.stiffness = 0.0;
    const double node_mass = ameoto::make_lattice_ball(spec).info.node_mass;
    spec.stiffness = node_mass * std::pow(10.0 / kT, 2) / 24.0;   // omega_max T = 10 (Gershgorin)
    auto excite = [](Body3D& body) { randomise_velocities(body, 3, Vec3{}, 0.01); };

    SUBCASE("sub-stepped: finite, undamped energy kept") {
        auto ball = ameoto::make_lattice_ball(spec);
        excite(ball.body);
        REQUIRE(ball.body.finalize(kT).sub_steps == 6);
        ball.body.step();
        const double e0 = ball.body.energy();
        double worst = 0.0;
        for (int n = 0; n < 5000; ++n) {
            CHECK_NOTHROW(ball.body.step());
            worst = std::max(worst, std::abs(ball.body.energy() - e0) / e0);
        }
        CHECK(ball.body.resets() == 0);
        CHECK(std::isfinite(ball.body.position(0).x));
        // Stable: the measured energy ripples with omega T' (about 1.7 per sub-step here), it does not grow.
        CHECK(worst < 1.0);
    }
    SUBCASE("forced to one sub-step, with an energy limit: caught within a few steps") {
        auto ball = ameoto::make_lattice_ball(spec);
        excite(ball.body);
        CHECK_FALSE(ball.body.finalize(kT, 1).stable());
        const double e0 = ball.body.kinetic_energy();
        ball.body.set_energy_limit(100.0 * e0);
        int caught_at = -1;
        for (int n = 0; n < 100 && caught_at < 0; ++n)
            if (!ball.body.step()) caught_at = n;
        CHECK(caught_at >= 0);
        CHECK(caught_at < 20);   // omega T = 10 grows a mode about 100x per step
        CHECK(ball.body.resets() == 1);
        // Reset: every mass back where it started, at rest.
        auto fresh = ameoto::make_lattice_ball(spec);
        for (int i = 0; i < ball.body.mass_count(); ++i) {
            CHECK(ameoto::norm(ball.body.position(i) - fresh.body.position(i)) == 0.0);
            CHECK(ameoto::norm(ball.body.velocity(i)) == 0.0);
        }
        // Still unstable: the rounding in the rest state (link lengths equal h to an ulp) grows about 100x
        // per step and diverges again; each time the guard catches it. The guard reads the energy the
        // step measured at the start of its last sub-step (body3d.hpp), so what it lets through is at most
        // one sub-step's growth beyond the limit: the amplitude factor |lambda| of
        // lambda^2 - (2 - (omega T)^2) lambda + 1 is below (omega T)^2 = 100, the energy's below 1e4.
        double worst = 0.0;
        for (int n = 0; n < 200; ++n) {
            ball.body.step();
            worst = std::max(worst, ball.body.energy() / (100.0 * e0));
        }
        CHECK(worst < 1e4);
        CHECK(ball.body.resets() > 1);
    }
    SUBCASE("forced to one sub-step, no energy limit: the non-finite state is caught") {
        auto ball = ameoto::make_lattice_ball(spec);
        excite(ball.body);
        ball.body.finalize(kT, 1);
        double peak = 0.0;
        int caught_at = -1;
        for (int n = 0; n < 2000 && caught_at < 0; ++n) {
            if (!ball.body.step()) caught_at = n;
            else peak = std::max(peak, ball.body.energy());
        }
        CHECK(caught_at > 0);
        CHECK(peak > 1e100);   // it really diverged before going non-finite
        CHECK(ball.body.resets() == 1);
        CHECK(std::isfinite(ball.body.position(0).x));
    }
}

TEST_CASE("body3d: state edits, integrator switch, reset, and step before finalize") {
    const double m = 1e-6;
    Body3D body;
    const int a = body.add_mass(m, Vec3{1.0, 2.0, 3.0});
    CHECK_FALSE(body.step());   // not finalized: does nothing
    CHECK(body.position(a).x == 1.0);
    body.set_velocity(a, Vec3{0.5, 0.0, 0.0});
    body.finalize(kT);
    CHECK(body.velocity(a).x == ameoto::test::relative(0.5).epsilon(1e-9));
    body.step();
    CHECK(body.position(a).x == doctest::Approx(1.0 + 0.5 * kT).epsilon(1e-14));
    body.set_integrator(Integrator::symplectic_euler);
    CHECK(body.velocity(a).x == ameoto::test::relative(0.5).epsilon(1e-9));
    body.set_position(a, Vec3{0.0, 0.0, 0.0});
    CHECK(body.velocity(a).x == ameoto::test::relative(0.5).epsilon(1e-9));
    body.set_integrator(Integrator::explicit_verlet);
    CHECK(body.velocity(a).x == ameoto::test::relative(0.5).epsilon(1e-9));
    // The implicit and modal schemes are not Body3D's: refused, nothing changes.
    CHECK_FALSE(body.set_integrator(Integrator::trapezoidal));
    CHECK_FALSE(body.set_integrator(Integrator::modal));
    CHECK(body.integrator() == Integrator::explicit_verlet);
    body.apply_force(a, Vec3{0.0, 1.0, 0.0});
    body.step();
    CHECK(body.velocity(a).y == ameoto::test::relative(kT / m).epsilon(1e-9));
    body.step();   // the external force was cleared after its step
    CHECK(body.velocity(a).y == ameoto::test::relative(kT / m).epsilon(1e-9));
    body.reset();
    CHECK(body.position(a).x == 1.0);   // the position at finalize()
    CHECK(ameoto::norm(body.velocity(a)) == 0.0);
    // finalize() again at another step keeps the velocity and takes the new rest state.
    body.set_velocity(a, Vec3{0.0, 0.0, 2.0});
    body.step();
    body.finalize(2.0 * kT);
    CHECK(body.velocity(a).z == doctest::Approx(2.0).epsilon(1e-9));
    const Vec3 here = body.position(a);
    body.step();
    body.reset();
    CHECK(ameoto::norm(body.position(a) - here) == 0.0);
}

TEST_CASE("body3d: construction rejects bad input") {
    Body3D body;
    CHECK_THROWS_AS(body.add_mass(0.0, Vec3{}), std::invalid_argument);
    CHECK_THROWS_AS(body.add_mass(-1.0, Vec3{}), std::invalid_argument);
    CHECK_THROWS_AS(body.add_mass(std::nan(""), Vec3{}), std::invalid_argument);
    CHECK_THROWS_AS(body.add_mass(1.0, Vec3{std::nan(""), 0.0, 0.0}), std::invalid_argument);
    const int a = body.add_mass(1.0, Vec3{}), b = body.add_mass(1.0, Vec3{1.0, 0.0, 0.0});
    CHECK_THROWS_AS(body.add_spring(a, a, 1.0, 0.0, 1.0), std::invalid_argument);
    CHECK_THROWS_AS(body.add_spring(a, 2, 1.0, 0.0, 1.0), std::invalid_argument);
    CHECK_THROWS_AS(body.add_spring(-1, b, 1.0, 0.0, 1.0), std::invalid_argument);
    CHECK_THROWS_AS(body.add_spring(a, b, -1.0, 0.0, 1.0), std::invalid_argument);
    CHECK_THROWS_AS(body.add_spring(a, b, 1.0, 0.0, -1.0), std::invalid_argument);
    CHECK_THROWS_AS(body.add_breakable(a, b, 1.0, 0.0, 1.0, 0.0), std::invalid_argument);
    CHECK_THROWS_AS(body.set_linear_drag(a, -1.0), std::invalid_argument);
    CHECK_THROWS_AS(body.set_quadratic_drag(a, std::nan("")), std::invalid_argument);
    CHECK_THROWS(body.set_linear_drag(5, 1.0));
    CHECK_THROWS_AS(body.finalize(0.0), std::invalid_argument);
    CHECK(body.link_count() == 0);
    CHECK(body.mass_count() == 2);
}

TEST_CASE("body3d: step() never allocates or locks, with breaks, contacts, drag and forces") {
    auto ball = mixed_ball(12.5, 1e-5, 1.5e-4);
    Body3D& body = ball.body;
    body.set_gravity(Vec3{0.0, 0.0, -9.80665});
    for (int i = 0; i < body.mass_count(); ++i) {
        body.set_linear_drag(i, 1.77e-8);
        body.set_quadratic_drag(i, 1e-8);
    }
    randomise_velocities(body, 5, Vec3{0.0, 0.0, -4.0}, 0.1);
    body.set_energy_limit(1.0);
    body.finalize(kT);
    ameoto::test::RtAudit audit;
    int breaks = 0;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int n = 0; n < 2000; ++n) {
            body.apply_force(n % body.mass_count(), Vec3{1e-4, 0.0, 0.0});
            body.step();
            breaks += static_cast<int>(body.breaks().size());
            if (n == 1000) {
                body.set_integrator(Integrator::symplectic_euler);
                body.set_velocity(0, Vec3{0.0, 0.0, -5.0});
            }
        }
        body.reset();
    }
    CHECK(breaks > 0);
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
}

// positions() (the collision broad phase's bulk read) gives position(m) for every mass, as the body moves.
TEST_CASE("body3d: positions() reads every mass as position(m)") {
    Body3D body;
    for (int i = 0; i < 5; ++i) body.add_mass(1e-6, Vec3{0.001 * i, -0.002 * i, 0.5 + 0.001 * i});
    for (int i = 0; i + 1 < 5; ++i) body.add_spring(i, i + 1, 0.1, 1e-6, 0.0015);
    body.set_gravity(Vec3{0.0, 0.0, -9.80665});
    body.finalize(kT);
    body.set_velocity(4, Vec3{0.3, 0.0, -1.0});
    for (int n = 0; n < 50; ++n) body.step();
    const Body3D::Coordinates c = body.positions();
    for (int m = 0; m < body.mass_count(); ++m) {
        CHECK(c.x[m] == body.position(m).x);
        CHECK(c.y[m] == body.position(m).y);
        CHECK(c.z[m] == body.position(m).z);
    }
    CHECK(c.z[0] != 0.5);   // it moved (springs and gravity)
}
