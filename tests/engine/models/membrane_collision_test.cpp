// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/membrane_collision: drop masses against the canopy (seed section 4.3). These
// are the seed's exchange (CollisionOptions::seed()); the wet law's tests are wet_impact_test.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/core/random.hpp"
#include "engine/models/membrane_collision.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using ameoto::Vec3;

namespace {

constexpr double kDropMass = 5.24e-7;   // kg, the seed's 1 mm drop mass (physics.md s.1)

// Drop masses integrated by symplectic Euler (v += T F / m; x += T v), as Body3D can: then x - T v is
// exactly the previous position, which the swept test relies on.
struct TestMasses {
    std::vector<Vec3> x, v, f;
    std::vector<double> m;
    bool gravity = true;

    int count() const { return static_cast<int>(x.size()); }
    Vec3 position(int i) const { return x[static_cast<std::size_t>(i)]; }
    Vec3 velocity(int i) const { return v[static_cast<std::size_t>(i)]; }
    double mass(int i) const { return m[static_cast<std::size_t>(i)]; }
    void apply_force(int i, Vec3 force) { f[static_cast<std::size_t>(i)] = f[static_cast<std::size_t>(i)] + force; }
    void add(Vec3 position, Vec3 velocity, double mass) {
        x.push_back(position);
        v.push_back(velocity);
        f.push_back({});
        m.push_back(mass);
    }
    void step() {
        for (std::size_t i = 0; i < x.size(); ++i) {
            Vec3 force = f[i];
            if (gravity) force.z -= m[i] * ameoto::constants::gravity;
            v[i] = v[i] + (kT / m[i]) * force;
            x[i] = x[i] + kT * v[i];
            f[i] = {};
        }
    }
};
static_assert(ameoto::CollisionMasses<TestMasses>);

// The shape of DropPool (models/drop_pool.hpp): drops by id, masses within a drop.
struct TestPool {
    std::vector<int> ids;
    std::vector<TestMasses> drops;   // by id
    std::span<const int> active() const { return ids; }
    int mass_count(int d) const { return drops[static_cast<std::size_t>(d)].count(); }
    Vec3 position(int d, int m) const { return drops[static_cast<std::size_t>(d)].position(m); }
    Vec3 velocity(int d, int m) const { return drops[static_cast<std::size_t>(d)].velocity(m); }
    double mass(int d, int m) const { return drops[static_cast<std::size_t>(d)].mass(m); }
    void apply_force(int d, int m, Vec3 f) { drops[static_cast<std::size_t>(d)].apply_force(m, f); }
};
static_assert(ameoto::CollisionDrops<TestPool>);
static_assert(ameoto::CollisionMasses<ameoto::MassArrays>);

// Height above the membrane, as the collider measures it (membrane_collision.hpp).
double height(const ameoto::Canopy& c, Vec3 p) {
    const auto hit = c.locate(p.x, p.y);
    return (p.z - c.rest_height(p.x, p.y)) * c.surface_normal(p.x, p.y).z - c.displacement(hit.panel, hit.node);
}

ameoto::Canopy make_canopy(double curvature = std::numeric_limits<double>::infinity()) {
    return ameoto::Canopy(ameoto::CanopyGeometry{8, 0.5, 50, curvature}, ameoto::MembraneMaterial::nylon_canopy(), kT);
}

}  // namespace

TEST_CASE("membrane_collision: one elastic collision exchanges momentum exactly and keeps the energy") {
    auto canopy = make_canopy();
    ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions::seed());
    std::vector<double> forces(8);
    // A drop mass just through the membrane over node 20 of panel 3, falling at 6.5 m/s (2 mm terminal speed).
    const auto at = canopy.rest_position(3, 20);
    TestMasses drops;
    drops.gravity = false;
    const double v0 = -6.5;
    drops.add({at.x, at.y, 0.5 * kT * v0}, {0.0, 0.0, v0}, kDropMass);
    std::vector<ameoto::MembraneCollision> log;
    CHECK(collider.collide(canopy, drops, [&](const ameoto::MembraneCollision& c) { log.push_back(c); }) == 1);
    REQUIRE(log.size() == 1);
    const auto& c = log[0];
    CHECK(c.panel == 3);
    CHECK(c.node == 20);
    CHECK(c.m1 == kDropMass);
    CHECK(c.m2 == canopy.panel(3).network.mass(20));
    CHECK(c.v1 == v0);
    CHECK(c.v2 == 0.0);
    // Seed 4.3: momentum and kinetic energy conserved (rounding: 1e-15 relative).
    const double p_before = c.m1 * c.v1 + c.m2 * c.v2, p_after = c.m1 * c.v1_after + c.m2 * c.v2_after;
    CHECK(std::abs(p_after - p_before) <= 1e-15 * std::abs(p_before));
    const double e_before = 0.5 * (c.m1 * c.v1 * c.v1 + c.m2 * c.v2 * c.v2);
    const double e_after = 0.5 * (c.m1 * c.v1_after * c.v1_after + c.m2 * c.v2_after * c.v2_after);
    CHECK(e_after == ameoto::test::relative(e_before).epsilon(1e-14));
    // The textbook elastic result (membrane_collision.hpp, e = 1).
    const double m1 = c.m1, m2 = c.m2;
    CHECK(c.v1_after == ameoto::test::relative(((m1 - m2) * v0) / (m1 + m2)).epsilon(1e-14));
    CHECK(c.v2_after == ameoto::test::relative(2.0 * m1 * v0 / (m1 + m2)).epsilon(1e-14));
    CHECK(c.impulse == ameoto::test::relative(m1 * (c.v1_after - c.v1)).epsilon(1e-14));

    // The exchange acts as the force m (v' - v) / T over one step (seed 4.3): after both bodies step,
    // their velocities are v1' and v2' (the node starts from rest, so no link acts within that step).
    canopy.step(forces.data());
    drops.step();
    CHECK(drops.v[0].z == ameoto::test::relative(c.v1_after).epsilon(1e-13));
    CHECK(drops.v[0].x == 0.0);   // frictionless: tangential components untouched
    CHECK(drops.v[0].y == 0.0);
    CHECK(canopy.normal_velocity(3, 20) == ameoto::test::relative(c.v2_after).epsilon(1e-12));
    const double p_stepped = m1 * drops.v[0].z + m2 * canopy.normal_velocity(3, 20);
    CHECK(std::abs(p_stepped - p_before) <= 1e-12 * std::abs(p_before));
    // And the panel's net force over that step is the node's share: -J / T (renderer's F_net).
    CHECK(forces[3] == ameoto::test::relative(-c.impulse / kT).epsilon(1e-12));
    CHECK(collider.collisions() == 1);
}

TEST_CASE("membrane_collision: restitution below 1 loses (1/2) mu (1 - e^2) v_rel^2, momentum still exact") {
    for (double e : {0.0, 0.3, 0.7, 1.0}) {
        CAPTURE(e);
        auto canopy = make_canopy(1.5);   // curved, and the membrane already moving
        std::vector<double> forces(8);
        canopy.apply_force({2, 17}, 0.05);
        for (int n = 0; n < 30; ++n) canopy.step(forces.data());
        ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions{e, 1e-3, ameoto::ImpactModel::seed});
        const auto at = canopy.node_position(2, 17), n = canopy.normal(2, 17);
        TestMasses drops;
        const Vec3 v{1.5, -0.7, -5.0};   // oblique
        drops.add(at - (0.2 * kT * 5.0) * n, v, 3.0 * kDropMass);
        std::vector<ameoto::MembraneCollision> log;
        CHECK(collider.collide(canopy, drops, [&](const ameoto::MembraneCollision& c) { log.push_back(c); }) == 1);
        REQUIRE(log.size() == 1);
        const auto& c = log[0];
        CHECK(c.node == 17);
        CHECK(c.v2 == canopy.normal_velocity(2, 17));
        CHECK(c.v2 != 0.0);
        const double m1 = c.m1, m2 = c.m2, mu = m1 * m2 / (m1 + m2), vrel = c.v1 - c.v2;
        // membrane_collision.hpp, the closed forms.
        CHECK(c.v1_after == ameoto::test::relative(((m1 - e * m2) * c.v1 + (1 + e) * m2 * c.v2) / (m1 + m2)).epsilon(1e-12));
        CHECK(c.v2_after == ameoto::test::relative(((m2 - e * m1) * c.v2 + (1 + e) * m1 * c.v1) / (m1 + m2)).epsilon(1e-12));
        const double p0 = m1 * c.v1 + m2 * c.v2, p1 = m1 * c.v1_after + m2 * c.v2_after;
        CHECK(std::abs(p1 - p0) <= 1e-15 * (std::abs(m1 * c.v1) + std::abs(m2 * c.v2)));
        const double e0 = 0.5 * (m1 * c.v1 * c.v1 + m2 * c.v2 * c.v2);
        const double e1 = 0.5 * (m1 * c.v1_after * c.v1_after + m2 * c.v2_after * c.v2_after);
        const double loss = 0.5 * mu * (1.0 - e * e) * vrel * vrel;
        CHECK(std::abs((e0 - e1) - loss) <= 1e-12 * e0);
        // The force on the drop lies along the node's normal: the tangential velocity is unchanged.
        drops.gravity = false;
        drops.step();
        const Vec3 dv = drops.v[0] - v;
        CHECK(ameoto::norm(dv - ameoto::dot(dv, n) * n) < 1e-12 * ameoto::norm(dv));
        CHECK(ameoto::dot(drops.v[0], n) == ameoto::test::relative(c.v1_after).epsilon(1e-12));
    }
}

TEST_CASE("membrane_collision: several masses on one node in one step are sequential pairwise collisions") {
    auto canopy = make_canopy();
    ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions::seed());
    const auto at = canopy.rest_position(0, 25);
    TestMasses drops;
    for (int i = 0; i < 5; ++i) drops.add({at.x + 1e-4 * i, at.y, -1e-5}, {0.0, 0.0, -3.0 - i}, kDropMass);
    std::vector<ameoto::MembraneCollision> log;
    CHECK(collider.collide(canopy, drops, [&](const ameoto::MembraneCollision& c) { log.push_back(c); }) == 5);
    double p0 = canopy.panel(0).network.mass(25) * canopy.normal_velocity(0, 25), p1 = p0;
    double e0 = 0.5 * canopy.panel(0).network.mass(25) * canopy.normal_velocity(0, 25) * canopy.normal_velocity(0, 25);
    for (const auto& c : log) {
        p0 += c.m1 * c.v1;
        e0 += 0.5 * c.m1 * c.v1 * c.v1;
    }
    // Each collision starts from the node velocity the previous one left.
    for (std::size_t i = 1; i < log.size(); ++i) CHECK(log[i].v2 == ameoto::test::relative(log[i - 1].v2_after).epsilon(1e-15));
    double e1 = 0.5 * log.back().m2 * log.back().v2_after * log.back().v2_after;
    p1 = log.back().m2 * log.back().v2_after;
    for (const auto& c : log) {
        p1 += c.m1 * c.v1_after;
        e1 += 0.5 * c.m1 * c.v1_after * c.v1_after;
    }
    CHECK(p1 == ameoto::test::relative(p0).epsilon(1e-14));
    CHECK(e1 == ameoto::test::relative(e0).epsilon(1e-14));
    // After both step, the node's velocity is the last v2' (from rest: no link acts in that step).
    std::vector<double> forces(8);
    canopy.step(forces.data());
    CHECK(canopy.normal_velocity(0, 25) == ameoto::test::relative(log.back().v2_after).epsilon(1e-12));
    // A new step forgets this step's pending velocities.
    TestMasses one;
    one.add({at.x, at.y, canopy.node_position(0, 25).z - 1e-6}, {0.0, 0.0, -9.0}, kDropMass);
    log.clear();
    collider.collide(canopy, one, [&](const ameoto::MembraneCollision& c) { log.push_back(c); });
    REQUIRE(log.size() == 1);
    CHECK(log[0].v2 == canopy.normal_velocity(0, 25));
}

TEST_CASE("membrane_collision: who does not collide") {
    auto canopy = make_canopy();
    ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions::seed());
    const auto at = canopy.rest_position(5, 10);
    TestMasses drops;
    drops.add({at.x, at.y, 1e-4}, {0.0, 0.0, -5.0}, kDropMass);      // above the membrane
    drops.add({at.x, at.y, -1e-5}, {0.0, 0.0, 2.0}, kDropMass);      // below, but leaving
    drops.add({at.x, at.y, -5e-3}, {0.0, 0.0, -5.0}, kDropMass);     // under the canopy (beyond swept + skin)
    drops.add({0.6, 0.0, -1e-5}, {0.0, 0.0, -5.0}, kDropMass);       // outside the canopy
    drops.add({0.48, 0.0, -1e-5}, {0.0, 0.0, -5.0}, kDropMass);      // between the hem chord and the rim
    CHECK(collider.collide(canopy, drops) == 0);
    // Just within swept depth + skin: collides.
    TestMasses deep;
    deep.add({at.x, at.y, -(kT * 5.0 + 0.9e-3)}, {0.0, 0.0, -5.0}, kDropMass);
    CHECK(collider.collide(canopy, deep) == 1);
    CHECK_THROWS_AS(ameoto::MembraneCollider(canopy, kT, ameoto::CollisionOptions{1.1, 1e-3}), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::MembraneCollider(canopy, kT, ameoto::CollisionOptions{-0.1, 1e-3}), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::MembraneCollider(canopy, 0.0), std::invalid_argument);
}

TEST_CASE("membrane_collision: no drop mass tunnels through, up to 20 m/s at 48 kHz (and far beyond)") {
    // Each mass starts a few mm above the surface at a random point, falls at the given speed
    // (vertically or obliquely), and is followed for 10 ms. Swept test (membrane_collision.hpp): it is
    // never found deeper than the distance closed in one step, T |v1 - v2| (+ rounding), and ends above.
    for (double rc : {std::numeric_limits<double>::infinity(), 1.2}) {
        for (double speed : {0.5, 2.0, 6.5, 9.2, 15.0, 20.0, 100.0}) {
            CAPTURE(rc);
            CAPTURE(speed);
            auto canopy = make_canopy(rc);
            ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions::seed());
            ameoto::Random rng(static_cast<std::uint64_t>(speed * 10));
            TestMasses drops;
            for (int i = 0; i < 40; ++i) {
                ameoto::Point2 p = canopy.sample_point(rng);
                p.x *= 0.9;   // keep off the hem, where a mass may legitimately slide off the canopy
                p.y *= 0.9;
                const double tilt = (i % 2) ? 0.0 : 0.5;   // every other mass falls at about 27 degrees
                const double a = rng.uniform(0.0, 2.0 * ameoto::constants::pi);
                const Vec3 v = (speed / std::sqrt(1.0 + tilt * tilt)) * Vec3{tilt * std::cos(a), tilt * std::sin(a), -1.0};
                drops.add({p.x - 1e-3 * v.x, p.y - 1e-3 * v.y, canopy.rest_height(p.x, p.y) + 1e-3 * speed + 1e-3 * rng.uniform()},
                          v, kDropMass);
            }
            std::vector<double> forces(8);
            std::vector<double> deepest(drops.x.size(), 0.0), closing(drops.x.size(), 0.0);
            int collisions = 0;
            for (int n = 0; n < 480; ++n) {
                collisions += collider.collide(canopy, drops, [&](const ameoto::MembraneCollision& c) {
                    const auto i = static_cast<std::size_t>(c.mass);
                    deepest[i] = std::max(deepest[i], c.depth);
                    closing[i] = std::max(closing[i], c.v2 - c.v1);
                });
                canopy.step(forces.data());
                drops.step();
            }
            CHECK(collisions >= 40);
            for (std::size_t i = 0; i < drops.x.size(); ++i) {
                CAPTURE(i);
                // Never deeper than one step's travel (gravity adds at most 0.1 m/s in 10 ms; the
                // membrane moves at mm/s).
                CHECK(deepest[i] > 0.0);
                CHECK(deepest[i] <= kT * (speed + 0.2));
                // Flat canopy, vertical fall: the swept bound itself, to rounding (the surface under the
                // mass is the same node's plane before and after).
                if (!(rc < 1e9) && i % 2 == 1) CHECK(deepest[i] <= kT * closing[i] + 1e-15);
                const auto hit = canopy.locate(drops.x[i].x, drops.x[i].y);
                if (hit.panel >= 0) CHECK(height(canopy, drops.x[i]) > 0.0);   // bounced back up, not through
                CHECK(drops.v[i].z > 0.0);
            }
        }
    }
}

TEST_CASE("membrane_collision: collide never allocates") {
    auto canopy = make_canopy(1.5);
    ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions{0.5, 1e-3, ameoto::ImpactModel::seed});
    std::vector<Vec3> x, v, f(200);
    std::vector<double> m(200, kDropMass);
    ameoto::Random rng(3);
    for (int i = 0; i < 200; ++i) {
        const auto p = canopy.sample_point(rng);
        x.push_back({p.x, p.y, canopy.rest_height(p.x, p.y) - 1e-5});
        v.push_back({0.0, 0.0, -4.0});
    }
    ameoto::MassArrays masses{x, v, m, f};
    std::vector<double> forces(8);
    int hits = 0;
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope s;
        for (int n = 0; n < 20; ++n) {
            hits += collider.collide(canopy, masses);
            canopy.step(forces.data());
        }
    }
    CHECK(hits >= 200);
    CHECK(audit.entries() > 0);
    CHECK(audit.violations() == 0);
    CHECK(audit.first() == "none");
    for (const auto& force : f) CHECK(force.z > 0.0);   // every mass was pushed back up
}

TEST_CASE("membrane_collision: drops indexed by drop and mass (the pool's shape)") {
    auto canopy = make_canopy();
    ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions::seed());
    const auto at = canopy.rest_position(6, 30);
    TestPool pool;
    pool.drops.resize(3);
    pool.ids = {0, 2};   // drop 1 is not active
    for (int d = 0; d < 3; ++d)
        for (int m = 0; m < 4; ++m)
            pool.drops[static_cast<std::size_t>(d)].add({at.x + 1e-3 * m, at.y + 1e-3 * d, m < 2 ? -1e-5 : 1e-3},
                                                        {0.0, 0.0, -4.0}, kDropMass);
    std::vector<ameoto::MembraneCollision> log;
    CHECK(collider.collide_drops(canopy, pool, [&](const ameoto::MembraneCollision& c) { log.push_back(c); }) == 4);
    REQUIRE(log.size() == 4);
    CHECK(log[0].drop == 0);
    CHECK(log[2].drop == 2);
    CHECK(log[3].mass == 1);
    for (int d : {0, 2})
        for (int m = 0; m < 4; ++m)
            CHECK((pool.drops[static_cast<std::size_t>(d)].f[static_cast<std::size_t>(m)].z > 0.0) == (m < 2));
    for (const auto& f : pool.drops[1].f) CHECK(f.z == 0.0);
}
