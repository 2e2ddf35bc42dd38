// SPDX-License-Identifier: GPL-3.0-or-later
// DropOnCanopy: a lattice drop on the canopy, end to end (engine/models/drop_on_canopy.hpp).
#include "engine/models/drop_on_canopy.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/models/drop.hpp"

#include "tests/support/rt_probe_scope.hpp"

namespace {

using ameoto::DropOnCanopy;
using ameoto::DropOnCanopyConfig;
using ameoto::ListenerStyle;
using ameoto::SceneOutput;

DropOnCanopyConfig small_config() {
    DropOnCanopyConfig c;
    c.max_diameter = 5.2e-3;   // lattices up to 140 masses: quick to build
    return c;
}

struct Render {
    std::vector<std::vector<float>> channels;
    double peak = 0.0;
    bool finite = true;
};

Render render(DropOnCanopy& scene, int frames) {
    Render r;
    r.channels.assign(static_cast<std::size_t>(scene.channels()), std::vector<float>(static_cast<std::size_t>(frames)));
    std::vector<float*> out;
    for (auto& c : r.channels) out.push_back(c.data());
    constexpr int block = 256;
    for (int done = 0; done < frames; done += block) {
        std::vector<float*> at;
        for (float* p : out) at.push_back(p + done);
        scene.process(std::min(block, frames - done), at.data());
    }
    for (const auto& c : r.channels)
        for (float s : c) {
            if (!std::isfinite(s)) r.finite = false;
            r.peak = std::max(r.peak, static_cast<double>(std::fabs(s)));
        }
    return r;
}

}  // namespace

TEST_CASE("drop_on_canopy: a 5 mm water drop at terminal speed breaks up on nylon, masses conserved exactly") {
    DropOnCanopy scene(small_config());
    REQUIRE(scene.drop(5e-3, 0.0, 0.2, 0.0));
    const auto before = scene.stats();
    CHECK(before.active_drops == 1);
    CHECK(before.pieces == 1);
    CHECK(before.masses == 122);
    const Render r = render(scene, 4800);   // 0.1 s
    const auto s = scene.stats();
    MESSAGE("5 mm water on nylon after 0.1 s: ", s.pieces, " pieces, ", s.breakups, " breakups, ", s.link_breaks,
            " link breaks, ", s.collisions, " collisions, peak ", r.peak);
    CHECK(s.active_drops == 1);
    CHECK(s.pieces > 1);
    CHECK(s.breakups == s.pieces - 1);
    CHECK(s.collisions > 0);
    CHECK(s.masses == s.masses_at_spawn);
    CHECK(s.masses == 122);
    CHECK(s.mass_kg == s.mass_at_spawn_kg);   // exact: no mass created or removed
    CHECK(s.canopy_resets == 0);
    CHECK(r.finite);
    CHECK(r.peak > 0.0);
    CHECK(scene.snapshot().size() == 122u);
}

TEST_CASE("drop_on_canopy: a 0.5 mm drop is one mass and stays whole") {
    // Before settling (with it, the mass at rest on the membrane is parked and its drop retires within
    // 50 ms: drop_settle_test.cpp).
    DropOnCanopyConfig c = small_config();
    c.settle = false;
    DropOnCanopy scene(c);
    REQUIRE(scene.drop(0.5e-3, 0.0, 0.2, 0.0));
    const Render r = render(scene, 2400);
    const auto s = scene.stats();
    CHECK(s.masses == 1);
    CHECK(s.pieces == 1);
    CHECK(s.breakups == 0);
    CHECK(s.collisions > 0);
    CHECK(s.mass_kg == s.mass_at_spawn_kg);
    CHECK(r.finite);
    CHECK(r.peak > 0.0);
}

TEST_CASE("drop_on_canopy: drop() refuses what it cannot place") {
    DropOnCanopy scene(small_config());
    CHECK_FALSE(scene.drop(6e-3, 0.0, 0.2, 0.0));    // above max_diameter
    CHECK_FALSE(scene.drop(0.0, 0.0, 0.2, 0.0));
    CHECK_FALSE(scene.drop(3e-3, -1.0, 0.2, 0.0));   // negative speed
    CHECK_FALSE(scene.drop(3e-3, 0.0, 2.0, 0.0));    // off the canopy
    CHECK(scene.drop(3e-3, 0.0, 0.2, 0.0));
    CHECK(scene.stats().spawned == 1);
}

TEST_CASE("drop_on_canopy: bad configurations are refused with a reason") {
    DropOnCanopyConfig c = small_config();
    c.channels = 0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c.channels = 17;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.guard_interval = -1;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.sample_rate = 100.0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.restitution = 1.5;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.liquid.density = 1.0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    for (int coarse : {0, 65}) {
        c = small_config();
        c.coarse_steps = coarse;
        CHECK_THROWS_WITH_AS(DropOnCanopy{c}, ("coarse steps " + std::to_string(coarse) + " is outside 1..64").c_str(),
                             std::invalid_argument);
    }
}

TEST_CASE("drop_on_canopy: a splash in flight takes coarse steps; the sound is every-sample stepping's, bit for bit, until it lands again") {
    // drop_pool.hpp, "Coarse steps": a drop wholly over the membrane's highest point (read by collide()),
    // by more than it can travel, takes up to coarse_steps samples as one. Nothing touches it meanwhile,
    // so the canopy, and with it the sound, is exactly what stepping every sample gives until a piece
    // comes down again (a 5 mm splash on nylon rises for about 0.1 s and lands again after 0.5 s). What
    // the pieces' flight itself changes is symplectic Euler's error with the longer step: about
    // g t (k - 1) T / 2, 92 um after 0.3 s for k = 4 at 48 kHz (the most DropOnCanopy asks for).
    // The seed's exchange (ImpactModel::seed): its splash bounces up and flies for 0.1 s, the case coarse
    // steps are for. (A wet impact holds most of the drop on the membrane; its few pieces thrown up take
    // coarse steps the same way.)
    auto run = [](int coarse_steps, int frames, DropOnCanopy*& keep) {
        DropOnCanopyConfig c = small_config();
        c.impact = ameoto::ImpactModel::seed;
        c.coarse_steps = coarse_steps;
        c.settle = false;   // the coarse steps alone (with settling, pieces parked apart: drop_settle_test)
        keep = new DropOnCanopy(c);
        REQUIRE(keep->drop(5e-3, 0.0, 0.25, 0.0));
        return render(*keep, frames);
    };
    const int frames = static_cast<int>(0.3 * 48000);
    DropOnCanopy *coarse = nullptr, *fine = nullptr;
    const Render a = run(4, frames, coarse), b = run(1, frames, fine);
    const std::unique_ptr<DropOnCanopy> own_coarse(coarse), own_fine(fine);
    const auto& pool = coarse->pool().stats();
    MESSAGE(pool.coarse_steps << " coarse steps, " << pool.coarse_sat_out << " samples sat out of " << frames);
    CHECK(pool.coarse_steps > 1000);
    CHECK(pool.coarse_sat_out >= pool.coarse_steps);
    CHECK(pool.coarse_interrupted == 0);
    CHECK(pool.resets == 0);
    CHECK(fine->pool().stats().coarse_steps == 0);
    CHECK(a.channels == b.channels);   // the sound: bit for bit
    CHECK(a.peak > 0.0);
    const auto sa = coarse->stats(), sb = fine->stats();
    CHECK(sa.collisions == sb.collisions);
    CHECK(sa.pieces == sb.pieces);
    CHECK(sa.masses == sa.masses_at_spawn);   // conservation, exactly
    CHECK(sa.mass_kg == sa.mass_at_spawn_kg);
    // The pieces in flight: their centre of mass within 1.5 x that bound of every-sample stepping's.
    const double bound = 1.5 * 9.80665 * 0.3 * (4 - 1) / 48000.0 / 2.0;
    const auto ma = coarse->snapshot(), mb = fine->snapshot();
    REQUIRE(ma.size() == mb.size());
    ameoto::Vec3 da{};
    for (std::size_t i = 0; i < ma.size(); ++i) da = da + (ma[i].position - mb[i].position);
    da = da / static_cast<double>(ma.size());
    MESSAGE("centre of mass, coarse - fine: " << da.x * 1e6 << ", " << da.y * 1e6 << ", " << da.z * 1e6 << " um");
    CHECK(ameoto::norm(da) < bound);
    CHECK(ameoto::norm(da) > 0.0);   // the flight did change: the coarse steps were taken
}

TEST_CASE("drop_on_canopy: panned outputs put a drop on its side, over 2 to 16 speakers") {
    for (int channels : {2, 4, 16}) {
        CAPTURE(channels);
        DropOnCanopyConfig c = small_config();
        c.channels = channels;
        c.listener = ListenerStyle::panned;
        DropOnCanopy scene(c);
        REQUIRE(scene.drop(3e-3, 0.0, 0.0, 0.25));   // panel at azimuth +90 deg: the left
        const Render r = render(scene, 1200);
        std::vector<double> energy;
        for (const auto& ch : r.channels) {
            double e = 0.0;
            for (float v : ch) e += static_cast<double>(v) * v;
            energy.push_back(e);
        }
        const auto loudest = std::max_element(energy.begin(), energy.end()) - energy.begin();
        // panning.hpp: stereo puts +90 deg hard left (channel 0); a ring from front-left clockwise has
        // +90 deg between the first speaker (front-left) and the last (back-left).
        if (channels == 2) CHECK(loudest == 0);
        if (channels == 4) CHECK((loudest == 0 || loudest == 3));
        CHECK(energy[static_cast<std::size_t>(loudest)] > 0.0);
    }
}

TEST_CASE("drop_on_canopy: a drop placed with no gap strikes at once, heard one acoustic delay later") {
    DropOnCanopyConfig c = small_config();
    c.gap_m = 0.0;
    DropOnCanopy scene(c);
    REQUIRE(scene.drop(4e-3, 0.0, 0.2, 0.05));
    float frame[1];
    scene.process_frame(frame);
    CHECK(scene.stats().collisions > 0);   // its lowest mass touches the cap in the first step
    CHECK(scene.acoustic_delay_samples(0.2, 0.05) > scene.latency_samples());
    CHECK(scene.latency_samples() == 42);   // 0.3 m under the shaft top, 343 m/s, 48 kHz: 0.29 m / 7.15 mm
}

TEST_CASE("drop_on_canopy: the same inputs render the same samples, bit for bit") {
    auto once = [] {
        DropOnCanopyConfig c = small_config();
        c.channels = 2;
        DropOnCanopy scene(c);
        scene.drop(3e-3, 0.0, 0.15, 0.05);
        scene.drop(2e-3, 5.0, -0.1, 0.2);
        return render(scene, 2400);
    };
    const Render a = once(), b = once();
    REQUIRE(a.channels.size() == 2u);
    CHECK(a.channels == b.channels);
    CHECK(a.peak > 0.0);
    CHECK(a.channels[0] != a.channels[1]);   // two ears hear different signals
}

TEST_CASE("drop_on_canopy: every material, liquid and output renders finite, non-silent audio") {
    for (const std::string& name : ameoto::membrane_material_names()) {
        DropOnCanopyConfig c = small_config();
        c.material = *ameoto::membrane_material(name);
        const bool seed = name == "seed-nylon";
        const int frames = seed ? 1200 : 2400;   // seed-nylon: 27 sub-steps per sample
        for (const SceneOutput output : {SceneOutput::far_field, SceneOutput::mass_pickup}) {
            c.output = output;
            const auto t0 = std::chrono::steady_clock::now();
            DropOnCanopy scene(c);
            REQUIRE(scene.drop(3e-3, 0.0, 0.2, 0.05));
            const Render r = render(scene, frames);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const std::string what = name + (output == SceneOutput::far_field ? " far field" : " pickup");
            INFO(what);
            CHECK(r.finite);
            CHECK(r.peak > 0.0);
            if (seed) MESSAGE("seed-nylon: ", frames, " samples in ", seconds, " s (27 sub-steps)");
        }
    }
    for (const ameoto::Liquid& liquid : ameoto::liquids::presets()) {
        DropOnCanopyConfig c = small_config();
        c.liquid = liquid;
        DropOnCanopy scene(c);
        REQUIRE(scene.drop(3e-3, 0.0, 0.2, 0.05));
        const Render r = render(scene, 2400);
        INFO(liquid.name);
        CHECK(r.finite);
        CHECK(r.peak > 0.0);
        CHECK(scene.stats().mass_kg == scene.stats().mass_at_spawn_kg);
    }
}

TEST_CASE("drop_on_canopy: drop() and process() never allocate") {
    DropOnCanopyConfig c = small_config();
    c.channels = 2;
    DropOnCanopy scene(c);
    std::vector<float> left(256), right(256);
    float* out[] = {left.data(), right.data()};
    scene.process(256, out);   // warm up
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        scene.drop(5e-3, 0.0, 0.2, 0.0);
        for (int b = 0; b < 20; ++b) scene.process(256, out);   // impact and breakup
        scene.drop(2e-3, 0.0, -0.2, 0.1);
        for (int b = 0; b < 4; ++b) scene.process(256, out);
        (void)scene.stats();
    }
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    CHECK(scene.stats().pieces > 2);
    CHECK(scene.pool().stats().coarse_steps > 0);   // the splash's coarse steps ran inside the audit too
}

namespace {

// DropOnCanopy rebuilt from its parts, with every drop mass given to the collider (collide_drops: no
// broad phase), for comparison with the scene's own collide(), which skips the masses that cannot
// collide. It also counts the masses the broad phase's two depth tests would skip, to show the
// scenarios exercise both.
struct ReferenceScene {
    DropOnCanopyConfig config;
    double dt;
    ameoto::Canopy canopy;
    ameoto::DropPool pool;
    ameoto::MembraneCollider collider;
    ameoto::FarFieldRadiation far_field;
    int liquid = 0;
    std::vector<double> panel_forces, pressures;
    long frames = 0, skippable_above = 0, skippable_below = 0;
    double peak_u = 0.0;   // the membrane's largest |u| seen

    static ameoto::DropPoolConfig pool_config(const DropOnCanopyConfig& c) {   // drop_on_canopy.cpp's
        ameoto::DropPoolConfig p;
        p.capacity = c.capacity;
        p.max_diameter = c.max_diameter;
        p.time_step = 1.0 / c.sample_rate;
        p.max_sub_steps = 64;
        p.retire_below = c.retire_below_m;
        p.max_lifetime = c.max_lifetime_s;
        p.options.tilted = c.impact == ameoto::ImpactModel::wet;
        return p;
    }

    explicit ReferenceScene(const DropOnCanopyConfig& c)
        : config(c),
          dt(1.0 / c.sample_rate),
          canopy(c.geometry, c.material, dt),
          pool(pool_config(c)),
          collider(canopy, dt, ameoto::collision_options(c)),
          far_field(canopy, ameoto::ListenerLayout::mono(ameoto::Vec3{0.0, 0.0, -c.listener_below_m}), dt),
          panel_forces(static_cast<std::size_t>(canopy.panel_count()), 0.0),
          pressures(1, 0.0) {
        REQUIRE(c.channels == 1);
        REQUIRE(c.output == SceneOutput::far_field);
        liquid = pool.add_liquid(c.liquid);
    }

    bool drop(double diameter, double speed, double x, double y) {   // DropOnCanopy::drop's placement
        const double v = speed > 0.0 ? speed : ameoto::arrival_speed(diameter, config.liquid.density);
        const double reach =
            collider.reach(ameoto::calibrate_drop(diameter, config.liquid, pool.config().options).node_mass);
        const double touch = reach > 0.0 ? reach - 1e-9 : 0.0;
        const double z = canopy.rest_height(x, y) + pool.underside(diameter) + touch + config.gap_m;
        return pool.spawn(diameter, liquid, ameoto::Vec3{x, y, z}, ameoto::Vec3{0.0, 0.0, -v});
    }

    // Masses the exact test (over max u) and the travel-aware lower band (drop_on_canopy_collide.cpp) would
    // skip, evaluated here independently of the scene.
    void count_skippable() {
        // Wet: a mass touches up to its reach over a node and is held up to 3/7 of its parcel under it:
        // the bounds widen by the reach's cap (drop_on_canopy_collide.cpp).
        const double touch = config.impact == ameoto::ImpactModel::wet ? collider.options().max_reach_m : 0.0;
        const double r = canopy.geometry().radius_m, skin = collider.options().skin_m + touch;
        const double nz = canopy.surface_normal(r, 0.0).z, bottom = canopy.rest_height(r, 0.0);
        const ameoto::DisplacementRange u = canopy.displacement_range();
        const double u_max = u.highest;
        peak_u = std::max(peak_u, std::max(u.highest, -u.lowest));
        for (const int d : pool.active())
            for (int m = 0; m < pool.mass_count(d); ++m) {
                const ameoto::Vec3 p = pool.position(d, m), v = pool.velocity(d, m);
                if (p.x * p.x + p.y * p.y > r * r) continue;
                const double a = (p.z - canopy.rest_height(p.x, p.y)) * canopy.surface_normal(p.x, p.y).z;
                if (a > u_max + touch) ++skippable_above;
                if (p.z < bottom - (0.05 + skin + dt * (std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z))) / nz)
                    ++skippable_below;
            }
    }

    std::vector<float> render(int count) {
        std::vector<float> out(static_cast<std::size_t>(count));
        for (int i = 0; i < count; ++i) {
            if (i % 16 == 0) count_skippable();
            collider.collide_drops(canopy, pool);
            canopy.step(panel_forces.data());
            pool.step();
            far_field.process(canopy, pressures.data());
            out[static_cast<std::size_t>(i)] = static_cast<float>(pressures[0] * (1.0 / config.full_scale_pa));
            if ((++frames & 255) == 0) canopy.reset_unstable();
        }
        return out;
    }
};

}  // namespace

TEST_CASE("drop_on_canopy: the collision broad phase skips only masses that cannot collide (bit-identical)") {
    struct Drop {
        double diameter, speed, x, y;
    };
    struct Scenario {
        const char* name;
        ameoto::MembraneMaterial material;
        double curvature_m;   // infinity: flat
        std::vector<Drop> drops;
        double seconds;
        double sample_rate = 48000.0;
    };
    const double flat = std::numeric_limits<double>::infinity();
    const std::vector<Scenario> scenarios = {
        {"5 mm on nylon", ameoto::MembraneMaterial::nylon_canopy(), flat, {{5e-3, 0.0, 0.25, 0.0}}, 2.0},
        {"3 mm on vinyl", ameoto::MembraneMaterial::vinyl(), flat, {{3e-3, 0.0, 0.2, 0.05}}, 1.5},
        // Fewer than 24 masses: every mass inside the rim is looked up (no bounds read).
        {"2 mm and 1 mm on nylon", ameoto::MembraneMaterial::nylon_canopy(), flat,
         {{2e-3, 0.0, -0.1, 0.2}, {1e-3, 0.0, 0.3, -0.1}}, 0.5},
        // Curved (oblique incidence: the normal leans up to 19.5 deg), fast, near the hem and a rib, so
        // pieces run off the edge and fall under the cap inside the rim's circle.
        {"5 mm at 20 m/s on curved nylon, near the hem", ameoto::MembraneMaterial::nylon_canopy(), 1.5,
         {{5e-3, 20.0, 0.43, 0.02}}, 1.0},
        {"3 mm on curved vinyl, near a rib, and four more", ameoto::MembraneMaterial::vinyl(), 1.5,
         {{3e-3, 0.0, 0.3, 0.118}, {5e-3, 12.0, -0.2, 0.1}, {3e-3, 0.0, 0.1, -0.3}, {5e-3, 0.0, 0.05, 0.05},
          {3e-3, 0.0, -0.35, -0.2}},
         0.5},
        // Eight into one spot at 30 m/s on vinyl: the membrane moves by more than 12.5 mm, where collide()
        // reads its displacement every step.
        {"eight 5 mm at 30 m/s into one spot on vinyl", ameoto::MembraneMaterial::vinyl(), flat,
         {{5e-3, 30.0, 0.25, 0.0}, {5e-3, 30.0, 0.254, 0.003}, {5e-3, 30.0, 0.258, 0.006}, {5e-3, 30.0, 0.262, 0.0},
          {5e-3, 30.0, 0.266, 0.003}, {5e-3, 30.0, 0.27, 0.006}, {5e-3, 30.0, 0.274, 0.0}, {5e-3, 30.0, 0.278, 0.003}},
         0.2},
        // 1 mm (one mass) at 500 m/s at 8 kHz: 6 cm per step, through the membrane and more than the
        // fixed 5 cm band below it in one step; collide_one's swept test still catches it.
        {"1 mm at 500 m/s at 8 kHz", ameoto::MembraneMaterial::nylon_canopy(), flat, {{1e-3, 500.0, 0.2, -0.1}}, 0.5,
         8000.0},
    };
    long above = 0, below = 0;
    double peak_u = 0.0;
    std::uint64_t passed_over = 0;   // drops skipped whole (their lowest mass over the band)
    std::uint64_t passed_over_in_band = 0;   // ... or in it but over the membrane's highest u, read that step
    for (const Scenario& s : scenarios) {
        const std::string name = s.name;
        INFO(name);
        DropOnCanopyConfig c = small_config();
        c.material = s.material;
        c.geometry.curvature_radius_m = s.curvature_m;
        c.sample_rate = s.sample_rate;
        // Every drop stepped every sample, as the reference's pool does: coarse steps (drop_pool.hpp) take
        // their floor from collide()'s own reading of the membrane, which the reference does not make;
        // they have their own test below.
        // Nothing parked, as the reference pool parks nothing (settling has its own test:
        // drop_settle_test.cpp).
        c.settle = false;
        c.coarse_steps = 1;
        DropOnCanopy scene(c);
        ReferenceScene reference(c);
        for (const Drop& d : s.drops) {
            REQUIRE(scene.drop(d.diameter, d.speed, d.x, d.y));
            REQUIRE(reference.drop(d.diameter, d.speed, d.x, d.y));
        }
        const int frames = static_cast<int>(s.seconds * c.sample_rate);
        const Render r = render(scene, frames);
        const std::vector<float> want = reference.render(frames);
        const auto stats = scene.stats();
        passed_over += stats.drops_passed_over;
        passed_over_in_band += stats.drops_passed_over_in_band;
        MESSAGE(name, ": ", stats.masses_at_spawn, " masses, ", stats.collisions, " collisions, ", stats.pieces,
                " pieces, ", stats.drops_passed_over, " drop-steps passed over whole (", stats.drops_passed_over_in_band,
                " of them in the band); of the masses inside the rim, ",
                reference.skippable_above, " over max u and ", reference.skippable_below,
                " under the band (sampled every 16 steps); largest |u| seen ", reference.peak_u * 1e3, " mm");
        CHECK(stats.collisions > 0);
        CHECK(stats.collisions == reference.collider.collisions());
        CHECK(r.channels[0] == want);
        CHECK(r.peak > 0.0);
        // And the drops themselves, mass by mass.
        const auto masses = scene.snapshot();
        std::size_t i = 0;
        bool same = true;
        for (const int d : reference.pool.active())
            for (int m = 0; m < reference.pool.mass_count(d); ++m, ++i)
                same = same && i < masses.size() && masses[i].position.x == reference.pool.position(d, m).x &&
                       masses[i].position.y == reference.pool.position(d, m).y &&
                       masses[i].position.z == reference.pool.position(d, m).z &&
                       masses[i].velocity.z == reference.pool.velocity(d, m).z;
        CHECK(same);
        CHECK(i == masses.size());
        above += reference.skippable_above;
        below += reference.skippable_below;
        peak_u = std::max(peak_u, reference.peak_u);
    }
    CHECK(above > 0);
    CHECK(below > 0);
    CHECK(peak_u > 0.0125);   // some scene made collide() read u every step (drop_on_canopy_collide.cpp)
    CHECK(passed_over > 0);   // and some drop was skipped whole, by Body3D::lowest_z()
    CHECK(passed_over_in_band > 0);   // some of them in the band, over the highest u read (a hovering splash)
}

TEST_CASE("drop_on_canopy: a scene built on a copy of a prototype canopy renders the built scene's samples, bit for bit") {
    // What impact_templates.cpp relies on: the copy of a canopy never stepped is the canopy the
    // constructor builds. Curved and panned, so the far field's per-panel geometry is exercised too;
    // the prototype serves twice (a copy leaves it at rest).
    DropOnCanopyConfig c = small_config();
    c.channels = 2;
    c.listener = ListenerStyle::panned;
    c.geometry.curvature_radius_m = 0.9;
    auto run = [](DropOnCanopy& scene) {
        scene.drop(3e-3, 0.0, 0.15, 0.05);
        scene.drop(2e-3, 5.0, -0.1, 0.2);
        return render(scene, 2400);
    };
    DropOnCanopy built(c);
    const ameoto::Canopy prototype = DropOnCanopy::fresh_canopy(c);
    DropOnCanopy first(c, prototype), second(c, prototype);
    const Render a = run(built), b = run(first), d = run(second);
    REQUIRE(a.channels.size() == 2u);
    CHECK(a.peak > 0.0);
    CHECK(b.channels == a.channels);
    CHECK(d.channels == a.channels);
    CHECK(first.stats().collisions == built.stats().collisions);
    CHECK(first.latency_samples() == built.latency_samples());

    DropOnCanopyConfig other = c;
    other.geometry.masses_per_panel = 30;
    CHECK_THROWS_AS(DropOnCanopy(other, prototype), std::invalid_argument);
    DropOnCanopyConfig bad = c;
    bad.sample_rate = -1.0;
    CHECK_THROWS_AS(DropOnCanopy(bad, prototype), std::invalid_argument);   // the config is still checked
    CHECK_THROWS_AS(DropOnCanopy::fresh_canopy(bad), std::invalid_argument);
}
