// SPDX-License-Identifier: GPL-3.0-or-later
// The addresses of the full protocol (issue 7): queries, /scene, /notify, /version, /surfaces.
#include <doctest/doctest.h>

#include <string>

#include "protocol/address_table.hpp"
#include "tests/support/osc_shorthand.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace ameoto;
using namespace ameoto::protocol;

TEST_CASE("every settable value has a query: the address with no value asks for what is in effect") {
    const ProtocolContext c;
    for (const char* address : {"/rain/rate", "/rain/wind", "/rain/dsd", "/listener", "/lod", "/material/liquid", "/scene",
                                "/scene/load", "/notify", "/reply/port", "/gain", "/loudness", "/listener/orientation"}) {
        INFO(address);
        const AddressSpec* spec = find_address(address);
        REQUIRE(spec);
        CHECK(spec->query.available);
        CHECK(std::string(spec->query.reply).starts_with(std::string(address) + ".reply "));
        const Validation v = validate(message(address), c);
        REQUIRE(v.ok);
        CHECK(v.request.action == Action::query);
        CHECK(v.request.query_address == address);
        CHECK(v.request.query_text.empty());
    }
    // Addresses that set one of several things are asked with the name of that thing.
    for (const char* address : {"/material/surface", "/surface/set"}) {
        INFO(address);
        const Validation v = validate(message(address, {s("umbrella")}), c);
        REQUIRE(v.ok);
        CHECK(v.request.action == Action::query);
        CHECK(v.request.query_text == "umbrella");
        CHECK_FALSE(validate(message(address, {f(1)}), c).ok);                // a name is text
        CHECK_FALSE(validate(message(address, {s("../etc")}), c).ok);         // and a name, never a path
        CHECK_FALSE(validate(message(address), c).ok);                        // without it, nothing to ask about
    }
}

TEST_CASE("the table's queries are exactly the settable addresses; actions that are not settings have none") {
    for (const AddressSpec& spec : address_table()) {
        INFO(spec.address);
        const std::string a = spec.address;
        const bool settable_value = a == "/rain/rate" || a == "/rain/wind" || a == "/rain/dsd" || a == "/listener" || a == "/lod" ||
                                    a == "/material/liquid" || a == "/material/surface" || a == "/scene" || a == "/scene/load" ||
                                    a == "/surface/set" || a == "/notify" || a == "/accuracy" || a == "/reply/port" ||
                                    a == "/gain" || a == "/loudness" || a == "/canopy/air" || a == "/canopy/impact" ||
                                    a == "/listener/orientation";
        if (!settable_value) {
            CHECK_FALSE(spec.query.available);
            continue;
        }
        CHECK(spec.query.available);
        // A query form never collides with the setting form: it has fewer arguments than the required ones.
        std::size_t required = 0;
        for (const auto& arg : spec.arguments) required += arg.optional ? 0 : 1;
        CHECK(spec.query.arguments.size() < required);
    }
}

TEST_CASE("/scene loads like /scene/load and refuses paths the same way") {
    const ProtocolContext c;
    const Validation v = validate(message("/scene", {s("pond")}), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::load_scene);
    CHECK(v.request.scene_name == "pond");
    CHECK(validate(message("/scene", {s("../x")}), c).reason.find("not a path") != std::string::npos);
    CHECK_FALSE(validate(message("/scene", {f(1)}), c).ok);
    CHECK_FALSE(validate(message("/scene", {s("pond"), s("forest")}), c).ok);
}

TEST_CASE("/notify takes 1 or 0 only; /version and /surfaces take nothing") {
    const ProtocolContext c;
    auto v = validate(message("/notify", {i(1)}), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::notify);
    CHECK(v.request.notify_on);
    v = validate(message("/notify", {f(0)}), c);
    REQUIRE(v.ok);
    CHECK_FALSE(v.request.notify_on);
    CHECK(validate(message("/notify", {i(2)}), c).reason.find("outside 0..1") != std::string::npos);
    CHECK(validate(message("/notify", {f(0.5)}), c).reason.find("integer") != std::string::npos);
    CHECK(validate(message("/notify", {s("on")}), c).reason.find("expected a number") != std::string::npos);
    CHECK(validate(message("/version"), c).request.action == Action::version);
    CHECK(validate(message("/version", {i(1)}), c).reason.find("too many") != std::string::npos);
    v = validate(message("/surfaces"), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::query);
    CHECK(v.request.query_address == "/surfaces");
    CHECK_FALSE(validate(message("/surfaces", {s("x")}), c).ok);
}

TEST_CASE("/reply/port takes a UDP port 1..65535 or 0 (the sender's own); with no value it is its query") {
    const ProtocolContext c;
    auto v = validate(message("/reply/port", {i(7771)}), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::reply_port);
    CHECK(v.request.reply_port == 7771);
    v = validate(message("/reply/port", {f(0)}), c);
    REQUIRE(v.ok);
    CHECK(v.request.reply_port == 0);
    CHECK(validate(message("/reply/port", {i(65535)}), c).request.reply_port == 65535);
    CHECK(validate(message("/reply/port", {i(65536)}), c).reason.find("outside 0..65535") != std::string::npos);
    CHECK(validate(message("/reply/port", {i(-1)}), c).reason.find("outside 0..65535") != std::string::npos);
    CHECK(validate(message("/reply/port", {f(7771.5)}), c).reason.find("integer") != std::string::npos);
    CHECK(validate(message("/reply/port", {s("7771")}), c).reason.find("expected a number") != std::string::npos);
    CHECK(validate(message("/reply/port", {i(7771), i(1)}), c).reason.find("too many") != std::string::npos);
    v = validate(message("/reply/port"), c);
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::query);
    CHECK(v.request.query_address == "/reply/port");
}
