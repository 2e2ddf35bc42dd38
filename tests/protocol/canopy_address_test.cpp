// SPDX-License-Identifier: GPL-3.0-or-later
// /canopy/air and /canopy/impact in the address table: a query with no arguments; 1 or 0 (air), wet or
// seed (impact) edits the scene; anything else is refused with a reason and no request.
#include <doctest/doctest.h>

#include <string>

#include "protocol/address_table.hpp"
#include "tests/support/osc_shorthand.hpp"

namespace ameoto::protocol {

namespace {

Validation check(const char* address, std::vector<OscArgument> args) {
    DecodedMessage m;
    m.address = address;
    m.args = std::move(args);
    for (const auto& a : m.args) m.types += a.type;
    return validate(m, ProtocolContext{});
}

}  // namespace

TEST_CASE("/canopy/air: no arguments is a query; 1 and 0 edit the scene") {
    Validation v = check("/canopy/air", {});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::query);
    CHECK(v.request.query_address == "/canopy/air");
    v = check("/canopy/air", {OscArgument::from_int(1)});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::edit_scene);
    CHECK(v.request.edit.op == SceneEdit::Op::air);
    CHECK(v.request.edit.air);
    v = check("/canopy/air", {OscArgument::from_int(0)});
    REQUIRE(v.ok);
    CHECK(v.request.edit.op == SceneEdit::Op::air);
    CHECK_FALSE(v.request.edit.air);
}

TEST_CASE("/canopy/air: refusals say why") {
    for (const auto& args : {std::vector<OscArgument>{OscArgument::from_int(2)}, std::vector<OscArgument>{OscArgument::from_int(-1)},
                             std::vector<OscArgument>{OscArgument::from_string("on")},
                             std::vector<OscArgument>{OscArgument::from_int(1), OscArgument::from_int(1)}}) {
        const Validation v = check("/canopy/air", args);
        CHECK_FALSE(v.ok);
        CHECK_FALSE(v.reason.empty());
    }
}

TEST_CASE("/canopy/impact: no arguments is a query; wet and seed edit the scene; other names refused") {
    Validation v = check("/canopy/impact", {});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::query);
    CHECK(v.request.query_address == "/canopy/impact");
    v = check("/canopy/impact", {OscArgument::from_string("seed")});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::edit_scene);
    CHECK(v.request.edit.op == SceneEdit::Op::impact);
    CHECK(v.request.edit.impact == ImpactModel::seed);
    v = check("/canopy/impact", {OscArgument::from_string("wet")});
    REQUIRE(v.ok);
    CHECK(v.request.edit.impact == ImpactModel::wet);
    for (const auto& args : {std::vector<OscArgument>{OscArgument::from_string("elastic")}, std::vector<OscArgument>{OscArgument::from_int(1)},
                             std::vector<OscArgument>{OscArgument::from_string("wet"), OscArgument::from_string("seed")}}) {
        const Validation bad = check("/canopy/impact", args);
        CHECK_FALSE(bad.ok);
        CHECK_FALSE(bad.reason.empty());
    }
    CHECK(check("/canopy/impact", {OscArgument::from_string("dry")}).reason.find("'dry' is not wet or seed") != std::string::npos);
}

}  // namespace ameoto::protocol
