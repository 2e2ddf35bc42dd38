// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/drop_pool: a fixed-capacity pool of lattice drops for the audio thread.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/models/drop_pool.hpp"
#include "engine/scene/terminal_speed.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using ameoto::DropPool;
using ameoto::DropPoolConfig;
using ameoto::Vec3;

namespace {

// A rigid, frictionless, inelastic floor at z = 0 acting through the pool's force interface, as a
// collision module would (test only; the same floor as drop_test.cpp).
void floor_forces(DropPool& pool) {
    for (int d : pool.active())
        for (int m = 0; m < pool.mass_count(d); ++m) {
            const Vec3 p = pool.position(d, m);
            if (p.z >= 0.0) continue;
            const double mass = pool.mass(d, m), omega = 2e4;
            const double f = std::max(0.0, mass * omega * omega * (-p.z) - 2.0 * mass * omega * pool.velocity(d, m).z);
            pool.apply_force(d, m, Vec3{0.0, 0.0, f});
        }
}

DropPoolConfig small_config(int capacity = 16) {
    DropPoolConfig c;
    c.capacity = capacity;
    c.max_diameter = 5.2e-3;   // lattices up to 140 masses: quick to build
    c.time_step = kT;
    return c;
}

}  // namespace

TEST_CASE("drop_pool: construction sizes everything; liquids are checked when added") {
    DropPool pool(small_config(4));
    CHECK(pool.capacity() == 4);
    CHECK(pool.max_masses() >= 122);
    CHECK(pool.active().empty());
    CHECK(pool.lattice(125).mass_count() == 122);
    CHECK(pool.add_liquid(ameoto::liquids::water()) == 0);
    CHECK(pool.add_liquid(ameoto::liquids::milk()) == 1);
    CHECK(pool.add_liquid(ameoto::liquids::heavy_oil()) == 2);   // 2-3 sub-steps at 48 kHz
    CHECK(pool.liquid(1).name == "milk");

    // Bad values: the validation message, naming the field.
    try {
        pool.add_liquid(ameoto::Liquid{"grams", 1.0, 0.07, 1e-3});
        FAIL("accepted a density of 1 kg/m^3");
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()).find("density") != std::string::npos);
    }
    // Valid but too viscous for explicit steps at 48 kHz (pitch, 2.3e8 Pa s, is outside the range;
    // 1e3 Pa s is inside it): refused with the reason.
    try {
        pool.add_liquid(ameoto::Liquid{"tar", 1200.0, 0.03, 1e3});
        FAIL("accepted a liquid whose dampers need thousands of sub-steps");
    } catch (const std::invalid_argument& e) {
        MESSAGE(std::string(e.what()));
        CHECK(std::string(e.what()).find("sub-steps") != std::string::npos);
    }
    CHECK(pool.liquid_count() == 3);
    DropPoolConfig one = small_config(1);
    one.max_liquids = 1;
    DropPool single(one);
    single.add_liquid(ameoto::liquids::water());
    CHECK_THROWS_AS(single.add_liquid(ameoto::liquids::milk()), std::invalid_argument);
    DropPoolConfig none = small_config(1);
    none.capacity = 0;
    CHECK_THROWS_AS(DropPool{none}, std::invalid_argument);
    for (int coarse : {0, 65}) {   // coarse steps: 1 (off) to 64 samples as one
        DropPoolConfig bad = small_config(1);
        bad.coarse_max = coarse;
        CHECK_THROWS_WITH_AS(DropPool{bad}, "drop pool: coarse max must be in 1..64", std::invalid_argument);
    }
    // Off by default: no floor, one sample per step.
    CHECK(DropPoolConfig{}.coarse_max == 1);
    CHECK(pool.coarse_floor() == std::numeric_limits<double>::infinity());
}

// add_liquid's check is cached per process (drop_pool.cpp) by everything but the pool's limit: each
// pool must still get its own verdict, and the same refusal, whichever pool asked first.
TEST_CASE("drop_pool: add_liquid's cached check gives every pool the verdict of its own limit") {
    DropPoolConfig roomy = small_config(1);
    roomy.max_diameter = 3.1e-3;   // a configuration no other test uses: the first pool computes the check
    DropPoolConfig tight = roomy;
    tight.max_sub_steps = 1;       // heavy oil needs 2 from 3 mm at 48 kHz
    DropPool first(roomy);
    CHECK(first.add_liquid(ameoto::liquids::heavy_oil()) == 0);
    DropPool second(tight);
    std::string refusal;
    try {
        second.add_liquid(ameoto::liquids::heavy_oil());
        FAIL("a 1-sub-step pool accepted heavy oil");
    } catch (const std::invalid_argument& e) {
        refusal = e.what();
    }
    CHECK(refusal.find("needs 2 sub-steps per step (limit 1)") != std::string::npos);
    CHECK(second.add_liquid(ameoto::liquids::water()) == 0);   // water needs 1
    DropPool third(roomy);
    CHECK(third.add_liquid(ameoto::liquids::heavy_oil()) == 0);
    DropPool fourth(tight);
    try {
        fourth.add_liquid(ameoto::liquids::heavy_oil());
        FAIL("a 1-sub-step pool accepted heavy oil");
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()) == refusal);   // the same drop named, the same count
    }
    // Another time step is another question: at 24 kHz water's cores need more than one sub-step.
    DropPoolConfig slow = tight;
    slow.time_step = 2.0 * kT;
    DropPool fifth(slow);
    CHECK_THROWS_AS(fifth.add_liquid(ameoto::liquids::water()), std::invalid_argument);
}

// A performer sweeping a custom liquid's viscosity live makes a new cache key per value: the cache is
// bounded (32 keys, then it starts again), and every pool still gets the right verdict across the reset.
TEST_CASE("drop_pool: add_liquid's cache stays bounded through a sweep of custom liquids") {
    DropPoolConfig config = small_config(1);
    config.max_diameter = 1.2e-3;   // small lattices: 40 checks stay quick
    for (int i = 0; i < 40; ++i) {
        ameoto::Liquid custom = ameoto::liquids::water();
        custom.name = "sweep";
        custom.viscosity = 1.0e-3 * (1.0 + 0.05 * i);
        DropPool pool(config);
        CHECK(pool.add_liquid(custom) == 0);
        CHECK(DropPool::cached_liquid_checks() <= 32);
    }
    CHECK(DropPool::cached_liquid_checks() >= 1);
}

TEST_CASE("drop_pool: spawn places a calibrated drop at its arrival speed; full and bad spawns are counted") {
    DropPool pool(small_config(2));
    const int water = pool.add_liquid(ameoto::liquids::water());
    const Vec3 centre{0.1, 0.2, 0.3};
    REQUIRE(pool.spawn(3e-3, water, centre));
    const int d = pool.active()[0];
    CHECK(pool.mass_count(d) == 28);
    CHECK(pool.serial(d) == 1);
    CHECK(pool.pieces(d) == 1);
    CHECK(ameoto::norm(pool.body(d).centre_of_mass() - centre) < 1e-12);
    CHECK(pool.body(d).total_mass() == ameoto::test::relative(998.0 * ameoto::constants::pi * 27e-9 / 6.0).epsilon(1e-14));
    for (int m = 0; m < pool.mass_count(d); ++m) CHECK(pool.velocity(d, m).z == -ameoto::terminal_speed(3e-3));
    CHECK(pool.calibration(d).rayleigh_hz == doctest::Approx(ameoto::rayleigh_frequency(3e-3, ameoto::liquids::water())));

    CHECK(pool.spawn(0.5e-3, water, centre, Vec3{1.0, 0.0, -2.0}, ameoto::DragPreset::seed_linear));
    CHECK_FALSE(pool.spawn(1e-3, water, centre));   // full
    CHECK(pool.stats().refused == 1);
    CHECK_FALSE(pool.spawn(2e-3, 7, centre));      // no such liquid
    CHECK_FALSE(pool.spawn(6e-3, water, centre));  // above max_diameter
    CHECK_FALSE(pool.spawn(0.0, water, centre));
    CHECK_FALSE(pool.spawn(2e-3, water, Vec3{std::nan(""), 0.0, 0.0}, Vec3{}));
    CHECK(pool.stats().rejected == 4);
    CHECK(pool.stats().spawned == 2);
    pool.clear();
    CHECK(pool.active().empty());
    CHECK(pool.stats().retired == 2);
    CHECK(pool.spawn(1e-3, water, centre));
    CHECK(pool.serial(pool.active()[0]) == 3);
}

TEST_CASE("drop_pool: drops striking a floor break up; every drop's masses are conserved exactly") {
    DropPool pool(small_config(8));
    const int water = pool.add_liquid(ameoto::liquids::water());
    const double sizes[] = {0.5e-3, 1e-3, 2e-3, 3e-3, 5e-3};
    for (int i = 0; i < 5; ++i) REQUIRE(pool.spawn(sizes[i], water, Vec3{0.02 * i, 0.0, 0.5 * sizes[i]}));
    std::vector<double> mass_before;
    std::vector<int> count_before;
    for (int d : pool.active()) {
        mass_before.push_back(pool.body(d).total_mass());
        count_before.push_back(pool.mass_count(d));
    }
    for (int n = 0; n < static_cast<int>(0.02 / kT); ++n) {
        floor_forces(pool);
        pool.step();
    }
    REQUIRE(pool.active().size() == 5);
    for (std::size_t i = 0; i < 5; ++i) {
        const int d = pool.active()[i];
        CAPTURE(pool.calibration(d).diameter);
        CHECK(pool.body(d).total_mass() == mass_before[i]);   // exact
        CHECK(pool.mass_count(d) == count_before[i]);
        int in_pieces = 0;
        for (int p = 0; p < pool.pieces(d); ++p) in_pieces += pool.piece_size(d, p);
        CHECK(in_pieces == count_before[i]);
        for (int m = 0; m < pool.mass_count(d); ++m) CHECK(pool.piece_of(d, m) < pool.pieces(d));
        if (pool.calibration(d).diameter <= 1e-3) CHECK(pool.pieces(d) == 1);
        else CHECK(pool.pieces(d) > 1);
    }
    CHECK(pool.stats().link_breaks > 0);
    CHECK(pool.stats().breakups > 3);
    CHECK(pool.stats().resets == 0);
}

TEST_CASE("drop_pool: a dormant drop falls exactly as the full lattice does, and wakes when touched") {
    DropPool pool(small_config(2));
    const int water = pool.add_liquid(ameoto::liquids::water());
    REQUIRE(pool.spawn(3e-3, water, Vec3{0.0, 0.0, 1.0}, Vec3{0.5, 0.0, -2.0}));
    REQUIRE(pool.spawn(3e-3, water, Vec3{0.0, 0.0, 1.0}, Vec3{0.5, 0.0, -2.0}));
    const int a = pool.active()[0], b = pool.active()[1];
    CHECK(pool.dormant(a));
    pool.body(b);   // reading the body wakes it
    CHECK_FALSE(pool.dormant(b));
    for (int n = 0; n < 4800; ++n) pool.step();   // 0.1 s: from 2 m/s towards 8 m/s
    CHECK(pool.dormant(a));
    double worst_p = 0.0, worst_v = 0.0;
    for (int m = 0; m < pool.mass_count(a); ++m) {
        worst_p = std::max(worst_p, ameoto::norm(pool.position(a, m) - pool.position(b, m)));
        worst_v = std::max(worst_v, ameoto::norm(pool.velocity(a, m) - pool.velocity(b, m)));
    }
    MESSAGE("dormant vs lattice after 0.1 s: " << worst_p << " m, " << worst_v << " m/s");
    // Rounding: the lattice's links see positions differing by eps |x| (1e-16 m) and answer with
    // forces of k eps |x|; over 4800 steps that is far below 1e-12 m and 1e-9 m/s.
    CHECK(worst_p < 1e-12);
    CHECK(worst_v < 1e-9);
    CHECK(pool.velocity(a, 0).z < -2.5);   // it did fall, under gravity and drag
    // lowest_z() (the collision broad phase's bound) is the lowest position, dormant or awake, without
    // waking the drop.
    for (const int d : {a, b}) {
        double lowest = std::numeric_limits<double>::infinity();
        for (int m = 0; m < pool.mass_count(d); ++m) lowest = std::min(lowest, pool.position(d, m).z);
        CHECK(pool.lowest_z(d) == lowest);
    }
    CHECK(pool.dormant(a));
    // Touching it wakes it where it is.
    const Vec3 before = pool.position(a, 5);
    pool.apply_force(a, 5, Vec3{});
    CHECK_FALSE(pool.dormant(a));
    CHECK(ameoto::norm(pool.body(a).position(5) - before) < 1e-15);
}

TEST_CASE("drop_pool: drops retire by the caller's predicate or their lifetime; slots are reused") {
    DropPoolConfig config = small_config(2);
    config.retire_interval = 4;
    config.max_lifetime = 0.05;
    DropPool pool(config);
    const int water = pool.add_liquid(ameoto::liquids::water());
    // Done: below z = 0 (fell past a surface).
    pool.set_retire_predicate([](Vec3 p, Vec3) { return p.z < 0.0; });
    REQUIRE(pool.spawn(2e-3, water, Vec3{0.0, 0.0, 0.01}));      // 10 mm above: about 1.5 ms at 6.5 m/s
    REQUIRE(pool.spawn(2e-3, water, Vec3{0.0, 0.0, 1.0}, Vec3{}));   // at rest, 1 m up: falls 12 mm in 50 ms
    int steps = 0;
    while (pool.stats().retired == 0 && steps < 1000) {
        pool.step();
        ++steps;
    }
    CHECK(pool.stats().retired == 1);
    CHECK(steps * kT == ameoto::test::relative(0.01 / 6.49).epsilon(0.2));
    CHECK(pool.active().size() == 1);
    CHECK(pool.spawn(1e-3, water, Vec3{}));   // the freed slot
    // The second drop outlives max_lifetime: retired at 50 ms.
    for (int n = 0; n < static_cast<int>(0.05 / kT) + 2; ++n) pool.step();
    CHECK(pool.stats().retired >= 2);
    for (int d : pool.active()) CHECK(pool.serial(d) == 3);
    CHECK_THROWS_AS(pool.set_retire_predicate(nullptr), std::invalid_argument);
}

TEST_CASE("drop_pool: spawn, step, breakup and retirement never allocate or lock") {
    DropPool pool(small_config(16));
    const int water = pool.add_liquid(ameoto::liquids::water());
    const int oil = pool.add_liquid(ameoto::liquids::heavy_oil());
    // Done: off a 10 cm panel (the frictionless floor lets pieces slide), or at rest on it.
    pool.set_retire_predicate([](Vec3 p, Vec3 v) {
        return std::abs(p.x) > 0.1 || std::abs(p.y) > 0.1 || (p.z < 0.001 && ameoto::norm(v) < 0.01);
    });
    ameoto::test::RtAudit audit;
    long spawned = 0, retired_by_predicate = 0;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int n = 0; n < 4000; ++n) {
            if (n % 100 == 0) {   // 0.5 to 4.5 mm, every third one of heavy oil
                const double d = 0.5e-3 + 1e-3 * ((n / 100) % 5);
                spawned += pool.spawn(d, (n / 100) % 3 == 0 ? oil : water, Vec3{0.01 * (n % 7), 0.0, 0.004});
            }
            floor_forces(pool);
            pool.step();
        }
        retired_by_predicate = pool.stats().retired;
        pool.clear();
    }
    // Splashed pieces fly up to 3 m/s and are still in the air after 83 ms, so the pool fills up:
    // the spawns it refused are counted.
    MESSAGE(spawned << " spawned, " << pool.stats().refused << " refused, " << retired_by_predicate
                    << " retired by the predicate, " << pool.stats().breakups << " pieces gained by breakups");
    CHECK(spawned + pool.stats().refused == 40);
    CHECK(spawned >= 16);
    CHECK(retired_by_predicate > 0);   // single masses come to rest on the floor
    CHECK(pool.stats().breakups > 0);
    CHECK(pool.stats().retired == spawned);
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
}

TEST_CASE("drop_pool: the same spawns give bit-identical states") {
    auto run = [] {
        DropPool pool(small_config(4));
        const int water = pool.add_liquid(ameoto::liquids::water());
        std::vector<double> state;
        for (int n = 0; n < 1500; ++n) {
            if (n == 0) pool.spawn(4e-3, water, Vec3{0.0, 0.0, 0.003});
            if (n == 200) pool.spawn(2.5e-3, water, Vec3{0.01, 0.0, 0.002});
            floor_forces(pool);
            pool.step();
        }
        for (int d : pool.active())
            for (int m = 0; m < pool.mass_count(d); ++m) {
                const Vec3 p = pool.position(d, m), v = pool.velocity(d, m);
                state.insert(state.end(), {p.x, p.y, p.z, v.x, v.y, v.z});
            }
        state.push_back(static_cast<double>(pool.stats().link_breaks));
        return state;
    };
    const auto a = run(), b = run();
    CHECK(a.back() > 0.0);
    CHECK(a == b);
}

TEST_CASE("drop_pool: cost of a step (measured, reported in docs/engine.md)") {
    DropPool pool(small_config(16));
    const int water = pool.add_liquid(ameoto::liquids::water());
    pool.set_retire_predicate([](Vec3, Vec3) { return false; });
    auto ns_per_step = [&](int steps) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int n = 0; n < steps; ++n) pool.step();
        return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / steps;
    };
    // One 5 mm drop, dormant, then awake (intact, falling), then 16 awake.
    pool.spawn(5e-3, water, Vec3{0.0, 0.0, 10.0});
    const double dormant = ns_per_step(4800);
    pool.body(pool.active()[0]);
    const double one = ns_per_step(2400);
    for (int i = 1; i < 16; ++i) {
        pool.spawn(5e-3, water, Vec3{0.01 * i, 0.0, 10.0});
        pool.body(pool.active().back());
    }
    const double sixteen = ns_per_step(480);
    // Spawning: clear, add 122 masses and 537 links, finalize.
    pool.clear();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 16; ++i) pool.spawn(5e-3, water, Vec3{0.01 * i, 0.0, 10.0});
    const double spawn_ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / 16;
    MESSAGE("5 mm drop per step: dormant " << dormant << " ns, awake " << one << " ns; 16 awake " << sixteen
                                           << " ns (" << sixteen * 48000.0 * 1e-9 * 100.0 << " % of a core at 48 kHz); spawn "
                                           << spawn_ns << " ns");
    CHECK(dormant < one);
}
