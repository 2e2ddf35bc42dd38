// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/address_table.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

#include "tests/support/osc_shorthand.hpp"
#include "tests/support/relative_approx.hpp"
#include "tests/protocol/round_surface_context.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace ameoto;
using namespace ameoto::protocol;

TEST_CASE("/rain/rate accepts 0..500 mm/h as any number type") {
    for (const auto& arg : {f(0), f(500), i(30), d(12.5)}) {
        const Validation v = validate(message("/rain/rate", {arg}), ameoto::test::round_surface_context());
        REQUIRE(v.ok);
        CHECK(v.request.action == Action::enqueue);
        CHECK(v.request.command.kind == CommandKind::rain_rate);
        CHECK(v.request.command.values[0] == doctest::Approx(arg.number));
    }
}

TEST_CASE("/drop converts mm to m and keeps SI speeds and positions") {
    const Validation v = validate(message("/drop", {f(3.0), f(0.0), f(0.25), f(-0.1)}), ameoto::test::round_surface_context());
    REQUIRE(v.ok);
    CHECK(v.request.command.kind == CommandKind::drop);
    CHECK(v.request.command.values[0] == ameoto::test::relative(0.003));
    CHECK(v.request.command.values[1] == 0.0);
    CHECK(v.request.command.values[2] == ameoto::test::relative(0.25));
    CHECK(v.request.command.values[3] == ameoto::test::relative(-0.1));
    CHECK(validate(message("/drop", {f(3.0), f(5.0), f(0.25), f(0.0), s("umbrella")}), ameoto::test::round_surface_context()).ok);
}

TEST_CASE("bad input is refused with a reason that names what is wrong") {
    struct Case {
        DecodedMessage m;
        const char* needle;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<Case> cases = {
        {message("/rain/ratex", {f(1)}), "unknown address"},
        {message("/sync", {}), "expected 1 arguments, got 0"},
        {message("/rain/rate", {f(1), f(2)}), "too many arguments"},
        {message("/rain/rate", {s("30")}), "expected a number"},
        {message("/rain/rate", {d(nan)}), "not a finite number"},
        {message("/rain/rate", {d(inf)}), "not a finite number"},
        {message("/rain/rate", {d(-inf)}), "not a finite number"},
        {message("/rain/rate", {f(500.5)}), "outside 0..500"},
        {message("/rain/rate", {f(-1)}), "outside 0..500"},
        {message("/rain/rate", {d(500.0001)}), "500.0001 is outside 0..500"},
        {message("/drop", {f(0.05), f(0), f(0), f(0.2)}), "diameter (mm)"},
        {message("/drop", {f(9), f(0), f(0), f(0.2)}), "outside 0.1..8"},
        {message("/drop", {f(3), f(21), f(0), f(0.2)}), "speed (m/s)"},
        {message("/drop", {f(3), f(0), f(3), f(3)}), "not on surface"},
        {message("/drop", {f(3), f(0), f(0.1), f(0.1), s("pond")}), "no surface named 'pond'"},
        {message("/drop", {f(3), f(0), f(0.1), f(0.1), f(1)}), "expected a string"},
        {message("/drop", {f(3), f(0), f(0.1)}), "expected 4 to 5 arguments"},
        {message("/drop", {f(3), f(0), f(0.1), f(0.1), s(std::string(300, 'x'))}), "longer than 255"},
        {message("/sync", {f(1.5)}), "expected an integer"},
        {message("/sync", {d(3e9)}), "outside"},
        {message("/status", {i(1)}), "too many arguments"},
        {message("/quit", {s("now")}), "too many arguments"},
    };
    for (const auto& c : cases) {
        const Validation v = validate(c.m, ameoto::test::round_surface_context());
        INFO(c.m.address << " " << c.m.types << " -> " << v.reason);
        CHECK_FALSE(v.ok);
        CHECK(v.reason.find(c.needle) != std::string::npos);
    }
}

TEST_CASE("every address in the table refuses NaN, wrong types and extra arguments") {
    // Walks the table itself, so an address added later cannot skip validation.
    for (const AddressSpec& spec : address_table()) {
        INFO(std::string(spec.address));
        std::vector<OscArgument> good;
        for (const auto& a : spec.arguments) {
            if (a.optional) break;
            if (a.kind == ArgumentKind::text) good.push_back(s(a.example));
            else if (a.kind == ArgumentKind::integer) good.push_back(i(0));
            else good.push_back(f(std::max(a.min, std::min(a.max, 0.1))));
        }
        const auto ok = validate(message(spec.address, good), ameoto::test::round_surface_context());
        INFO(ok.reason);
        CHECK(ok.ok);
        auto extra = good;
        for (std::size_t n = extra.size(); n <= spec.arguments.size(); ++n) extra.push_back(f(0));
        CHECK_FALSE(validate(message(spec.address, extra), ameoto::test::round_surface_context()).ok);
        for (std::size_t k = 0; k < good.size(); ++k) {
            auto bad = good;
            if (spec.arguments[k].kind == ArgumentKind::text) {
                bad[k] = f(1);
            } else {
                bad[k] = d(std::numeric_limits<double>::quiet_NaN());
                CHECK_FALSE(validate(message(spec.address, bad), ameoto::test::round_surface_context()).ok);
                bad[k] = s("1");
            }
            CHECK_FALSE(validate(message(spec.address, bad), ameoto::test::round_surface_context()).ok);
        }
    }
}

TEST_CASE("/status, /sync and /quit map to their actions") {
    CHECK(validate(message("/status", {}), ameoto::test::round_surface_context()).request.action == Action::status);
    CHECK(validate(message("/quit", {}), ameoto::test::round_surface_context()).request.action == Action::quit);
    const auto v = validate(message("/sync", {i(-12)}), ameoto::test::round_surface_context());
    REQUIRE(v.ok);
    CHECK(v.request.command.kind == CommandKind::sync);
    CHECK(v.request.command.id == -12);
}

TEST_CASE("every text argument in the table carries a valid example") {
    for (const AddressSpec& spec : address_table())
        for (const auto& a : spec.arguments)
            if (a.kind == ArgumentKind::text) {
                INFO(std::string(spec.address) << " " << a.name);
                CHECK(std::string(a.example).size() > 0);
            }
}

TEST_CASE("/material/surface and /material/liquid: presets, custom definitions, and refusals") {
    const ProtocolContext c = ameoto::test::round_surface_context();
    auto v = validate(message("/material/surface", {s("umbrella"), s("vinyl")}), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::set_surface_material);
    CHECK(v.request.material->name == "vinyl");
    v = validate(message("/material/surface", {s("umbrella"), s("rubber"), f(0.5), f(300), f(30), d(1e-5)}), c);
    REQUIRE(v.ok);
    CHECK(v.request.material->tension == doctest::Approx(300));
    CHECK(validate(message("/material/surface", {s("umbrella"), s("rubber"), f(0.5)}), c).reason.find("all four") != std::string::npos);
    CHECK(validate(message("/material/surface", {s("pond"), s("nylon")}), c).reason.find("no surface") != std::string::npos);
    CHECK(validate(message("/material/surface", {s("umbrella"), s("nylon"), f(1), f(1), f(1), d(0)}), c).reason.find("preset") !=
          std::string::npos);
    v = validate(message("/material/liquid", {s("milk")}), c);
    REQUIRE(v.ok);
    CHECK(v.request.liquid->density == doctest::Approx(1030));
    v = validate(message("/material/liquid", {s("syrup"), f(1300), f(0.07), f(5)}), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::set_liquid);
    CHECK(validate(message("/material/liquid", {s("tea")}), c).reason.find("no liquid named 'tea'") != std::string::npos);
    CHECK(validate(message("/material/liquid", {s("a/b")}), c).reason.find("letters, digits") != std::string::npos);
    CHECK(validate(message("/material/liquid", {s("syrup"), f(13000000), f(0.07), f(5)}), c).reason.find("outside") != std::string::npos);
}
