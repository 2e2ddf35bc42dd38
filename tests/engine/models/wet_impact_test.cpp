// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/wet_impact: a drop strikes as a real one does (Gordillo, Sun & Cheng, J. Fluid
// Mech. 840:190, 2018; shared/reference/acoustics.md section 3), the seed's exchange stays as a preset,
// and the impact's energy is accounted for.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "engine/core/random.hpp"
#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/membrane_collision.hpp"
#include "engine/models/wet_impact.hpp"
#include "tests/support/test_constants.hpp"
#include "engine/core/physical_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

namespace {

ameoto::RigidImpact rigid(double diameter_m, double rate, ameoto::ImpactModel model, double seconds = 0.0) {
    ameoto::RigidImpactSpec s;
    s.diameter_m = diameter_m;
    s.sample_rate = rate;
    s.law.model = model;
    s.seconds = seconds;
    return ameoto::measure_rigid_impact(s);
}

const double kRhoWater = ameoto::liquids::water().density;

// Point masses stepped by symplectic Euler under gravity (membrane_collision_test.cpp's TestMasses).
struct Masses {
    std::vector<ameoto::Vec3> x, v, f;
    double m = 5.24e-7;   // kg: a 1 mm drop
    int count() const { return static_cast<int>(x.size()); }
    ameoto::Vec3 position(int i) const { return x[static_cast<std::size_t>(i)]; }
    ameoto::Vec3 velocity(int i) const { return v[static_cast<std::size_t>(i)]; }
    double mass(int) const { return m; }
    void apply_force(int i, ameoto::Vec3 force) { f[static_cast<std::size_t>(i)] = f[static_cast<std::size_t>(i)] + force; }
    void step() {
        for (std::size_t i = 0; i < x.size(); ++i) {
            ameoto::Vec3 force = f[i];
            force.z -= m * ameoto::constants::gravity;
            v[i] = v[i] + (kT / m) * force;
            x[i] = x[i] + kT * v[i];
            f[i] = {};
        }
    }
};

}  // namespace

// The three checks of acoustics.md section 3 ("checks worth holding a model to"), from Gordillo et al.
// (2018) and Soto et al. (2014): on a rigid target the impulse within 10 % of m V (the drop spreads and
// does not bounce), the peak within 25 % of 0.8 rho V^2 D^2 (Gordillo's peak for Oh < 0.1), the pulse
// length between 0.5 and 2 D / V; 1, 2 and 4 mm drops at Gunn & Kinzer's terminal speed. The length is
// the span that delivers the middle 90 % of the impulse (5 % to 95 %: 0.76 D / V for the impact law of
// impact_force.hpp). Held at the rates the engine runs (44.1, 48, 96 kHz).
TEST_CASE("wet_impact: 1, 2 and 4 mm drops on a rigid plane meet Gordillo et al.'s impulse, peak and length") {
    for (const double rate : {44100.0, 48000.0, 96000.0})
        for (const double d : {1e-3, 2e-3, 4e-3}) {
            const ameoto::RigidImpact r = rigid(d, rate, ameoto::ImpactModel::wet);
            const double j = r.impulse_n_s / r.momentum(), f = r.peak_n / r.gordillo_peak(kRhoWater),
                         len = r.length_s / r.tau();
            MESSAGE(rate, " Hz, ", std::lround(d * 1e3), " mm at ", r.speed_m_per_s, " m/s (", r.masses, " masses): J / mV ", j,
                    ", peak / 0.8 rho V^2 D^2 ", f, ", length / (D / V) ", len, ", ", r.pieces, " pieces");
            CHECK(std::fabs(j - 1.0) <= 0.10);
            CHECK(std::fabs(f - 1.0) <= 0.25);
            CHECK(len >= 0.5);
            CHECK(len <= 2.0);
        }
}

// The seed's elastic exchange returns each mass's momentum: about 2 m V (acoustics.md section 3: "an
// elastic rebound would deliver 2 m V"), held to the same 10 % as the wet check.
TEST_CASE("wet_impact: the seed preset still gives about 2 m V") {
    for (const double d : {1e-3, 2e-3, 4e-3}) {
        const ameoto::RigidImpact r = rigid(d, kFs, ameoto::ImpactModel::seed);
        MESSAGE("seed, ", std::lround(d * 1e3), " mm: J / mV ", r.impulse_n_s / r.momentum());
        CHECK(std::fabs(r.impulse_n_s / r.momentum() - 2.0) <= 0.2);
    }
}

// Where the energy goes over 20 ms: the initial kinetic energy and gravity's work equal what is left
// (motion, links' elastic energy) plus what was dissipated (the contact, the links' dampers, air drag)
// and what broken links held. Each term is measured on its own (wet_impact.cpp), so the sum can miss;
// it misses by the integrator's own error of the contact, which shrinks with the step: within 1 % of
// the initial kinetic energy at 960 kHz (measured 0.3-0.5 %), within 10 % at 48 kHz (measured 5-8 %).
TEST_CASE("wet_impact: the energy accounting sums to the initial energy; the splash flies") {
    for (const double d : {2e-3, 4e-3}) {
        const ameoto::RigidImpact fine = rigid(d, 960000.0, ameoto::ImpactModel::wet, 0.02);
        const ameoto::ImpactEnergy& e = fine.energy;
        MESSAGE(std::lround(d * 1e3), " mm at 960 kHz, of the initial kinetic energy: left moving ", e.kinetic / e.initial_kinetic,
                " (flying ", e.kinetic_flying / e.initial_kinetic, "), contact ", e.collision / e.initial_kinetic,
                ", dampers ", e.viscous / e.initial_kinetic, ", drag ", e.drag / e.initial_kinetic, ", broken ",
                e.broken / e.initial_kinetic, ", residual ", e.residual() / e.initial_kinetic);
        CHECK(std::fabs(e.residual()) <= 0.01 * e.initial_kinetic);
        CHECK(e.collision > 0.3 * e.initial_kinetic);   // the wet contact does not return the energy
        CHECK(e.broken > 0.0);
        CHECK(fine.pieces > 1);                          // it still breaks up
        const ameoto::RigidImpact coarse = rigid(d, kFs, ameoto::ImpactModel::wet, 0.02);
        CHECK(std::fabs(coarse.energy.residual()) <= 0.10 * coarse.energy.initial_kinetic);
    }
    // At 4 mm pieces leave the plane: kinetic energy in pieces with no mass touching it.
    const ameoto::RigidImpact r = rigid(4e-3, kFs, ameoto::ImpactModel::wet, 0.02);
    CHECK(r.energy.kinetic_flying > 0.0);
    // The seed's exchange keeps the energy in the bounce (none to the contact).
    const ameoto::RigidImpact seed = rigid(2e-3, kFs, ameoto::ImpactModel::seed, 0.02);
    CHECK(seed.energy.collision == 0.0);
    CHECK(seed.energy.kinetic > 0.7 * seed.energy.initial_kinetic);
}

TEST_CASE("wet_impact: the phase inverts the depth law; the impulse never pulls, never exceeds mu w") {
    // A(s) = s - s^(5/2) + (3/7) s^(7/2) (wet_impact.hpp).
    for (int i = 1; i < 100; ++i) {
        const double s = i / 100.0;
        const double a = s - std::pow(s, 2.5) + 3.0 / 7.0 * std::pow(s, 3.5);
        CHECK(ameoto::wet_phase(a) == ameoto::test::relative(s).epsilon(1e-6));
    }
    CHECK(ameoto::wet_phase(0.0) == 0.0);
    CHECK(ameoto::wet_phase(3.0 / 7.0) == 1.0);
    const ameoto::ContactLaw law{};
    const double m1 = law.liquid_density * ameoto::constants::pi / 6.0 * 1e-9, inf = std::numeric_limits<double>::infinity();
    const double l = law.parcel(m1);
    CHECK(l == ameoto::test::relative(1e-3).epsilon(1e-12));   // 0.52 mg of water: a 1 mm parcel
    CHECK(law.reach(m1) == ameoto::test::relative(0.5 * l));
    for (const double m2 : {1e-6, 1e-5, inf})
        for (int k = 0; k <= 40; ++k) {
            const double h = law.reach(m1) - k * 0.0125 * l;   // from touching to past the hold depth
            const ameoto::ContactImpulse c = ameoto::contact_impulse(law, m1, m2, h, -5.0, 0.0, kT);
            const double mu = std::isinf(m2) ? m1 : m1 * m2 / (m1 + m2);
            REQUIRE(c.contact);
            CHECK(c.impulse >= 0.0);
            CHECK(c.impulse <= mu * 5.0 * (1.0 + 1e-12));
            CHECK(c.dissipated >= 0.0);
        }
    // Above the reach, or separating: no contact.
    CHECK_FALSE(ameoto::contact_impulse(law, m1, inf, law.reach(m1) * 1.01, -5.0, 0.0, kT).contact);
    CHECK_FALSE(ameoto::contact_impulse(law, m1, inf, 0.0, 0.1, 0.0, kT).contact);
    // The seed's law is the exchange J = -(1 + e) mu closing, with reach 0.
    const ameoto::ContactLaw seed{ameoto::ImpactModel::seed, 1.0};
    CHECK(seed.reach(m1) == 0.0);
    CHECK_FALSE(ameoto::contact_impulse(seed, m1, 1e-5, 1e-6, -5.0, 0.0, kT).contact);
    const double mu = m1 * 1e-5 / (m1 + 1e-5);
    CHECK(ameoto::contact_impulse(seed, m1, 1e-5, -1e-6, -5.0, 0.0, kT).impulse == -(1.0 + 1.0) * mu * -5.0);
    CHECK(ameoto::find_impact_model("wet") == ameoto::ImpactModel::wet);
    CHECK(ameoto::find_impact_model("seed") == ameoto::ImpactModel::seed);
    CHECK_FALSE(ameoto::find_impact_model("dry").has_value());
}

// The scene: wet by default; on the canopy (membrane nodes far heavier than a drop's masses) the seed's
// exchange gives about twice the wet impulse.
TEST_CASE("wet_impact: drop_on_canopy is wet by default; its seed preset strikes about twice as hard") {
    CHECK(ameoto::DropOnCanopyConfig{}.impact == ameoto::ImpactModel::wet);
    double impulse[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k) {
        ameoto::DropOnCanopyConfig c;
        c.impact = k == 0 ? ameoto::ImpactModel::wet : ameoto::ImpactModel::seed;
        c.gap_m = 0.0;
        ameoto::DropOnCanopy scene(c);
        REQUIRE(scene.drop(2e-3, 0.0, 0.2, 0.0));
        float frame[1];
        for (int n = 0; n < 96; ++n) {   // 2 ms: the first strike, 6 D / V
            scene.process_frame(frame);
            impulse[k] += scene.contact_force().z * scene.time_step();
        }
    }
    const double mv = kRhoWater * kPi / 6.0 * 8e-9 * ameoto::arrival_speed(2e-3, kRhoWater);
    MESSAGE("2 mm on the nylon canopy: wet ", impulse[0] / mv, " m V, seed ", impulse[1] / mv, " m V");
    CHECK(impulse[0] / mv == ameoto::test::relative(1.0).epsilon(0.15));
    CHECK(impulse[1] / impulse[0] == doctest::Approx(2.0).epsilon(0.15));
}

// The wet contact on the canopy (MembraneCollider with CollisionOptions::wet()): a mass falling at 0.5 to
// 20 m/s, vertically or at 27 degrees, onto a flat or curved membrane is caught (the swept test of
// membrane_collision.hpp, with the hold depth added) and does not bounce: after 10 ms it is no deeper than
// the hold depth 3/7 l under its parcel's touch plus one step's travel, and hardly moves along the normal.
TEST_CASE("wet_impact: on the canopy a wet mass never tunnels and does not bounce") {
    for (const double rc : {std::numeric_limits<double>::infinity(), 1.2})
        for (const double speed : {0.5, 4.0, 9.2, 20.0}) {   // up to twice a raindrop's fastest (docs/impacts.md: 100 m/s)
            CAPTURE(rc);
            CAPTURE(speed);
            ameoto::Canopy canopy(ameoto::CanopyGeometry{8, 0.5, 50, rc}, ameoto::MembraneMaterial::nylon_canopy(), kT);
            ameoto::MembraneCollider collider(canopy, kT, ameoto::CollisionOptions::wet());
            const ameoto::ContactLaw law = collider.options().law();
            ameoto::Random rng(static_cast<std::uint64_t>(speed * 10) + 3);
            Masses drops;
            const double r = law.reach(drops.m), l = law.parcel(drops.m);
            for (int i = 0; i < 40; ++i) {
                ameoto::Point2 p = canopy.sample_point(rng);
                p.x *= 0.5;   // near the shaft: a mass sliding on the curved cap stays on it for 10 ms
                p.y *= 0.5;
                const double tilt = (i % 2) ? 0.0 : 0.5;
                const double a = rng.uniform(0.0, 2.0 * kPi);
                const ameoto::Vec3 v = (speed / std::sqrt(1.0 + tilt * tilt)) * ameoto::Vec3{tilt * std::cos(a), tilt * std::sin(a), -1.0};
                drops.x.push_back({p.x, p.y, canopy.rest_height(p.x, p.y) + r + 1e-3 * rng.uniform()});
                drops.v.push_back(v);
                drops.f.push_back({});
            }
            std::vector<double> forces(8);
            int collisions = 0;
            for (int n = 0; n < 480; ++n) {
                collisions += collider.collide(canopy, drops);
                canopy.step(forces.data());
                drops.step();
            }
            CHECK(collisions >= 40);
            for (std::size_t i = 0; i < drops.x.size(); ++i) {
                CAPTURE(i);
                const auto hit = canopy.locate(drops.x[i].x, drops.x[i].y);
                // An oblique mass slides on, frictionless, and may leave the canopy within the 10 ms; on
                // the curved cap even a vertical one keeps the speed along the slope and leaves the convex
                // surface curving away under it. A vertical one on the flat canopy stays where it struck.
                const bool vertical = i % 2 == 1 && !(rc < 1e9);
                if (vertical) REQUIRE(hit.panel >= 0);
                if (hit.panel < 0) continue;
                const ameoto::Vec3 p = drops.x[i];
                const double h = (p.z - canopy.rest_height(p.x, p.y)) * canopy.surface_normal(p.x, p.y).z -
                                 canopy.displacement(hit.panel, hit.node);
                // Not through: on the flat canopy within the hold depth and one step's travel; on the
                // curved cap a mass sliding from node to node is measured against each node's own plane
                // (membrane_collision.hpp), which differs by microns from the last one's: within the
                // collider's skin, the depth it still holds a mass at.
                const double slack = rc < 1e9 ? collider.options().skin_m : 1e-9;
                CHECK(h >= r - 3.0 / 7.0 * l - kT * speed - slack);
                if (!vertical) continue;
                // It does not bounce as the seed's exchange does (back up at its own speed): within 1 %
                // of its speed plus 0.05 m/s after 10 ms. A fast one is tossed a little by the membrane
                // springing back under it (measured 0.10 m/s after a 20 m/s strike: the membrane cannot
                // pull); up to 4 m/s it rests on it.
                CHECK(std::fabs(ameoto::dot(drops.v[i], canopy.normal(hit.panel, hit.node))) < 0.01 * speed + 0.05);
                if (speed <= 4.0) CHECK(h <= r);                         // touching, not bounced off
            }
        }
}
