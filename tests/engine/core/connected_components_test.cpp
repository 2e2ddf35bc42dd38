// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/connected_components: pieces of a body after links break.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/connected_components.hpp"
#include "engine/core/lattice_ball.hpp"
#include "engine/core/random.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

using ameoto::Body3D;
using ameoto::Vec3;

namespace {

// A chain of n masses along x, rest length 1 mm, breakable links (the middle one weaker if asked).
Body3D chain(int n, double spacing, double break_force, double middle_break_force) {
    Body3D body;
    for (int i = 0; i < n; ++i) body.add_mass(1e-4, Vec3{spacing * i, 0.0, 0.0});
    for (int i = 0; i + 1 < n; ++i)
        body.add_breakable(i, i + 1, 100.0, 0.0, 1e-3, i == (n - 1) / 2 ? middle_break_force : break_force);
    return body;
}

}  // namespace

TEST_CASE("connected_components: an intact body is one piece; a lone mass is its own") {
    auto ball = ameoto::make_lattice_ball({.diameter = 5e-3, .stiffness = 1.0});
    ball.body.add_mass(1e-6, Vec3{1.0, 0.0, 0.0});   // not linked
    ameoto::ConnectedComponents cc;
    cc.init(ball.body.mass_count());
    CHECK(cc.compute(ball.body) == 2);
    CHECK(cc.size_of(0) == ball.info.mass_count);
    CHECK(cc.size_of(1) == 1);
    CHECK(cc.component_of(ball.body.mass_count() - 1) == 1);
    for (int i = 0; i < ball.info.mass_count; ++i) CHECK(cc.component_of(i) == 0);
}

TEST_CASE("connected_components: a chain whose middle link breaks splits in two, masses conserved") {
    const int n = 9;
    // Pull the ends apart; the middle link (link 4, between masses 4 and 5) is the weakest.
    Body3D body = chain(n, 1e-3, 1.0, 0.05);
    body.finalize(kT);
    ameoto::ConnectedComponents cc;
    cc.init(n);
    REQUIRE(cc.compute(body) == 1);
    int breaks = 0, broke_link = -1;
    for (int step = 0; step < 48000 && breaks == 0; ++step) {
        body.apply_force(0, Vec3{-0.02, 0.0, 0.0});
        body.apply_force(n - 1, Vec3{0.02, 0.0, 0.0});
        body.step();
        for (const auto& e : body.breaks()) {
            ++breaks;
            broke_link = e.link;
        }
    }
    REQUIRE(breaks == 1);
    CHECK(broke_link == 4);
    CHECK(cc.compute(body) == 2);
    CHECK(cc.size_of(0) == 5);   // masses 0..4 (numbered from the lowest mass)
    CHECK(cc.size_of(1) == 4);   // masses 5..8
    CHECK(cc.size_of(0) + cc.size_of(1) == n);
    for (int i = 0; i < n; ++i) CHECK(cc.component_of(i) == (i <= 4 ? 0 : 1));
}

TEST_CASE("connected_components: breaking every link leaves one component per mass") {
    const int n = 12;
    // Laid out at 1.5 times the rest length: every link pulls 0.05 N, above its 0.01 N threshold.
    Body3D body = chain(n, 1.5e-3, 0.01, 0.01);
    body.finalize(kT);
    body.step();
    CHECK(body.breaks().size() == static_cast<std::size_t>(n - 1));
    ameoto::ConnectedComponents cc;
    cc.init(n);
    CHECK(cc.compute(body) == n);
    for (int i = 0; i < n; ++i) {
        CHECK(cc.component_of(i) == i);
        CHECK(cc.size_of(i) == 1);
    }
}

TEST_CASE("connected_components: generic links, contacts do not bind, labels by lowest mass") {
    // 0-3 and 1-2 and 2-4 bond; 3-1 has bonds = 0 (a contact or broken link).
    const std::vector<std::int32_t> a{0, 1, 2, 3, 7}, b{3, 2, 4, 1, 0};
    const std::vector<std::uint8_t> bonds{1, 1, 1, 0, 1};   // the last one is out of range: ignored
    ameoto::ConnectedComponents cc;
    cc.init(6);
    CHECK(cc.compute(5, a, b, bonds) == 2);
    CHECK(cc.components().size() == 5);
    CHECK(cc.component_of(0) == 0);
    CHECK(cc.component_of(3) == 0);
    CHECK(cc.component_of(1) == 1);
    CHECK(cc.component_of(2) == 1);
    CHECK(cc.component_of(4) == 1);
    CHECK(cc.size_of(0) == 2);
    CHECK(cc.size_of(1) == 3);
    // A Body3D's contact links do not bind either.
    Body3D body;
    const int p = body.add_mass(1.0, Vec3{}), q = body.add_mass(1.0, Vec3{1e-3, 0.0, 0.0});
    body.add_contact(p, q, 1.0, 0.0, 2e-3);
    CHECK(cc.compute(body) == 2);
    // More masses than init(): refused without growing.
    CHECK(cc.compute(7, a, b, bonds) == 0);
}

TEST_CASE("connected_components: compute() never allocates or locks") {
    auto ball = ameoto::make_lattice_ball({.diameter = 5e-3, .link_kind = ameoto::LinkKind::breakable,
                                           .stiffness = 12.5, .break_force = 1e-4});
    Body3D& body = ball.body;
    for (int i = 0; i < body.mass_count(); ++i) body.set_velocity(i, Vec3{0.0, 0.0, (i % 2) ? 0.3 : -0.3});
    body.finalize(kT);
    ameoto::ConnectedComponents cc;
    cc.init(body.mass_count());
    ameoto::test::RtAudit audit;
    int pieces = 0;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int n = 0; n < 200; ++n) {
            body.step();
            if (!body.breaks().empty()) pieces = cc.compute(body);
        }
    }
    CHECK(pieces > 1);
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    int total = 0;
    for (int c = 0; c < cc.count(); ++c) total += cc.size_of(c);
    CHECK(total == body.mass_count());
}

namespace {

// The same partition: one label map from a to b that is a bijection, and the same sizes.
bool same_partition(const ameoto::ConnectedComponents& a, const ameoto::ConnectedComponents& b, int masses) {
    if (a.count() != b.count()) return false;
    std::vector<int> a_to_b(static_cast<std::size_t>(a.count()), -1), b_to_a(static_cast<std::size_t>(b.count()), -1);
    for (int m = 0; m < masses; ++m) {
        const auto p = static_cast<std::size_t>(a.component_of(m)), q = static_cast<std::size_t>(b.component_of(m));
        if (a_to_b[p] < 0) a_to_b[p] = static_cast<int>(q);
        if (b_to_a[q] < 0) b_to_a[q] = static_cast<int>(p);
        if (a_to_b[p] != static_cast<int>(q) || b_to_a[q] != static_cast<int>(p)) return false;
    }
    for (int c = 0; c < a.count(); ++c)
        if (a.size_of(c) != b.size_of(a_to_b[static_cast<std::size_t>(c)])) return false;
    return true;
}

}  // namespace

TEST_CASE("connected_components: update() after random breaks gives compute()'s partition (fuzz)") {
    // Graphs: drop lattices of 1 to 600 masses (what the pool splits), chains (the longest paths a
    // bidirectional search can meet on) and sparse random graphs (many small pieces and cycles). Each is
    // broken in random batches, of 1 to 40 links (beyond max_searches_per_update: the fallback too), until
    // nothing bonds; after every batch update() must give compute()'s partition, and changed() must list
    // every component whose masses changed and no other.
    ameoto::Random rng(20261122);
    int batches = 0, splits_seen = 0, fallbacks = 0;
    for (int trial = 0; trial < 120; ++trial) {
        std::vector<std::int32_t> a, b;
        int masses = 0;
        const int kind = trial % 3;
        if (kind == 0) {
            const auto shape = ameoto::lattice_ball_shape(1 + static_cast<int>(rng.uniform() * 600));
            a = shape.link_a;
            b = shape.link_b;
            masses = shape.mass_count();
        } else if (kind == 1) {
            masses = 2 + static_cast<int>(rng.uniform() * 200);
            for (int i = 0; i + 1 < masses; ++i) {
                a.push_back(i);
                b.push_back(i + 1);
            }
        } else {
            masses = 2 + static_cast<int>(rng.uniform() * 300);
            const int links = static_cast<int>(masses * rng.uniform(0.5, 3.0));
            for (int l = 0; l < links; ++l) {
                a.push_back(static_cast<int>(rng.uniform() * masses));
                b.push_back(static_cast<int>(rng.uniform() * masses));   // self-links and repeats included
            }
        }
        const int links = static_cast<int>(a.size());
        std::vector<std::uint8_t> bonds(static_cast<std::size_t>(links), 1);
        std::vector<std::int32_t> intact(static_cast<std::size_t>(links));
        for (int l = 0; l < links; ++l) intact[static_cast<std::size_t>(l)] = l;
        ameoto::ConnectedComponents incremental, full;
        incremental.init(masses, links);
        full.init(masses, links);
        incremental.compute(masses, a, b, bonds);
        std::vector<int> before;
        while (!intact.empty()) {
            const int batch = std::min<int>(static_cast<int>(intact.size()), 1 + static_cast<int>(rng.uniform() * (trial % 4 == 3 ? 40 : 6)));
            std::vector<std::int32_t> broken;
            for (int k = 0; k < batch; ++k) {
                const auto pick = static_cast<std::size_t>(rng.uniform() * static_cast<double>(intact.size()));
                broken.push_back(intact[pick]);
                bonds[static_cast<std::size_t>(intact[pick])] = 0;
                intact[pick] = intact.back();
                intact.pop_back();
            }
            before.assign(incremental.components().begin(), incremental.components().end());
            const int count_before = incremental.count();
            const int n = incremental.update(masses, a, b, bonds, broken);
            full.compute(masses, a, b, bonds);
            ++batches;
            REQUIRE(n == full.count());
            REQUIRE(same_partition(incremental, full, masses));
            if (n > count_before) ++splits_seen;
            if (static_cast<int>(incremental.changed().size()) == n && n > count_before + 1) ++fallbacks;
            // changed(): a component is listed if and only if its set of masses is not one from before.
            std::vector<int> members_before(static_cast<std::size_t>(n), -2);   // -1: several old labels
            std::vector<int> sizes_now(static_cast<std::size_t>(n), 0);
            for (int m = 0; m < masses; ++m) {
                const auto c = static_cast<std::size_t>(incremental.component_of(m));
                ++sizes_now[c];
                const int old = before[static_cast<std::size_t>(m)];
                members_before[c] = members_before[c] == -2 || members_before[c] == old ? old : -1;
            }
            std::vector<int> old_sizes(static_cast<std::size_t>(count_before), 0);
            for (int m = 0; m < masses; ++m) ++old_sizes[static_cast<std::size_t>(before[static_cast<std::size_t>(m)])];
            std::vector<char> listed(static_cast<std::size_t>(n), 0);
            for (const int c : incremental.changed()) listed[static_cast<std::size_t>(c)] = 1;
            for (int c = 0; c < n; ++c) {
                const int old = members_before[static_cast<std::size_t>(c)];
                const bool unchanged = old >= 0 && old_sizes[static_cast<std::size_t>(old)] == sizes_now[static_cast<std::size_t>(c)];
                if (unchanged && listed[static_cast<std::size_t>(c)]) CHECK(static_cast<int>(incremental.changed().size()) == n);
                if (!unchanged) CHECK(listed[static_cast<std::size_t>(c)] == 1);
            }
        }
    }
    MESSAGE(batches << " batches, " << splits_seen << " with new pieces, " << fallbacks << " through the fallback");
    CHECK(batches > 1000);
    CHECK(splits_seen > 300);
}

TEST_CASE("connected_components: update() follows a tearing lattice ball step by step, without allocating") {
    // The drop pool's use: a ball whose halves fly apart, its breaks fed to update() after each step.
    auto ball = ameoto::make_lattice_ball({.diameter = 6e-3, .link_kind = ameoto::LinkKind::breakable,
                                           .stiffness = 12.5, .break_force = 1e-4});
    Body3D& body = ball.body;
    // Velocities growing with the distance from a plane (and a little random spread): the links far
    // out break first, the tear moves inward over many steps.
    ameoto::Random rng(7);
    for (int i = 0; i < body.mass_count(); ++i) {
        const double x = body.position(i).x / 3e-3;
        body.set_velocity(i, Vec3{0.4 * x * x * x + rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02), 0.0});
    }
    body.finalize(kT);
    ameoto::ConnectedComponents incremental, full;
    incremental.init(body.mass_count(), body.link_count());
    full.init(body.mass_count(), body.link_count());
    REQUIRE(incremental.compute(body) == 1);
    ameoto::test::RtAudit audit;
    int steps_with_breaks = 0, mismatches = 0, last = 1;
    for (int n = 0; n < 300; ++n) {
        body.step();
        if (body.breaks().empty()) continue;
        ++steps_with_breaks;
        {
            ameoto::test::RtAudit::Scope scope;
            last = incremental.update(body, body.breaks());
        }
        full.compute(body);
        if (!same_partition(incremental, full, body.mass_count())) ++mismatches;
    }
    MESSAGE(steps_with_breaks << " steps with breaks, " << last << " pieces");
    CHECK(steps_with_breaks > 5);
    CHECK(last > 1);
    CHECK(mismatches == 0);
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    // Without a link capacity (init(masses) alone) update() falls back to compute(): still right.
    ameoto::ConnectedComponents plain;
    plain.init(body.mass_count());
    plain.compute(body);
    CHECK(plain.update(body, body.breaks()) == full.count());
}
