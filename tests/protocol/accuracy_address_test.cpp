// SPDX-License-Identifier: GPL-3.0-or-later
// /accuracy in the address table: a query with no arguments, a budget in cents or dB, off; every bad
// form refused with a reason and no request.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "protocol/address_table.hpp"
#include "tests/support/osc_shorthand.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace ameoto;
using namespace ameoto::protocol;

namespace {

Validation check(std::vector<OscArgument> args) {
    DecodedMessage m;
    m.address = "/accuracy";
    m.args = std::move(args);
    for (const auto& a : m.args) m.types += a.type;
    return validate(m, ProtocolContext{});
}

}  // namespace

TEST_CASE("/accuracy: no arguments is a query") {
    const Validation v = check({});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::query);
    CHECK(v.request.query_address == "/accuracy");
    REQUIRE(find_address("/accuracy"));
    CHECK(std::string(find_address("/accuracy")->reply).find("/accuracy.reply") != std::string::npos);
}

TEST_CASE("/accuracy: a budget in cents or dB edits the scene; off removes it") {
    Validation v = check({s("cents"), f(5)});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::edit_scene);
    CHECK(v.request.edit.op == SceneEdit::Op::accuracy);
    REQUIRE(v.request.edit.accuracy);
    CHECK(v.request.edit.accuracy->measure == AccuracyMeasure::cents);
    CHECK(v.request.edit.accuracy->value == 5.0);
    v = check({s("db"), OscArgument::from_int(2)});
    REQUIRE(v.ok);
    CHECK(v.request.edit.accuracy->measure == AccuracyMeasure::decibels);
    CHECK(v.request.edit.accuracy->value == 2.0);
    v = check({s("off")});
    REQUIRE(v.ok);
    CHECK(v.request.edit.op == SceneEdit::Op::accuracy);
    CHECK_FALSE(v.request.edit.accuracy);
    CHECK(check({s("cents"), f(1200)}).ok);
    CHECK(check({s("db"), f(60)}).ok);
}

TEST_CASE("/accuracy: refusals say why") {
    struct Case {
        std::vector<OscArgument> args;
        const char* reason;
    };
    const std::vector<Case> cases = {
        {{s("cents")}, "give the budget: /accuracy cents VALUE"},
        {{s("dB"), f(1)}, "measure 'dB' is not one of cents, db, off"},
        {{s("off"), f(1)}, "'off' takes no budget"},
        {{s("db"), f(61)}, "accuracy budget must be 0.001 to 60 dB"},
        {{s("cents"), f(1300)}, "1300 is outside 0.001..1200"},
        {{s("cents"), f(0)}, "0 is outside 0.001..1200"},
        {{s("cents"), f(NAN)}, "not a finite number"},
        {{f(5)}, "expected a string"},
        {{s("cents"), f(5), f(1)}, "too many arguments"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.reason);
        const Validation v = check(c.args);
        CHECK_FALSE(v.ok);
        CHECK(v.reason.find(c.reason) != std::string::npos);
    }
}
