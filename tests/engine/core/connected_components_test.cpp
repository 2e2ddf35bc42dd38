// Tests for engine/core/connected_components: pieces of a body after links break.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/connected_components.hpp"
#include "engine/core/lattice_ball.hpp"
#include "tests/support/rt_probe_scope.hpp"

using ameoto::Body3D;
using ameoto::Vec3;

namespace {

constexpr double kT = 1.0 / 48000.0;

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
