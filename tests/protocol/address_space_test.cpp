// SPDX-License-Identifier: GPL-3.0-or-later
// The whole address space, walked from the protocol table itself (tests/protocol/table_cases.hpp):
// every address refuses every bad variant with a reason and builds nothing, as bytes through the
// daemon's receive path (protocol/receive.hpp). A new address in the table is covered without a
// line here. The same cases go over real UDP to the real daemon in
// tests/integration/address_space_test.cpp.

#include <doctest/doctest.h>

#include <string>

#include "protocol/receive.hpp"
#include "tests/protocol/table_cases.hpp"
#include "tests/protocol/round_surface_context.hpp"

using namespace ameoto;
using namespace ameoto::protocol;

namespace {

ReceivedPacket receive(const std::vector<unsigned char>& bytes) { return receive_packet(bytes.data(), bytes.size(), ameoto::test::round_surface_context()); }

// A refusal builds nothing: the request is as default-constructed.
bool builds_nothing(const Request& r) {
    const Request none;
    return r.action == none.action && r.command.kind == none.command.kind && r.command.id == 0 &&
           r.command.values[0] == 0.0 && r.command.values[1] == 0.0 && r.command.values[2] == 0.0 &&
           r.command.values[3] == 0.0 && !r.liquid && !r.material && r.surface.empty() && r.scene_name.empty() &&
           r.edit.dsd.empty() && r.edit.surface.name.empty();
}

}  // namespace

TEST_CASE("the table test covers every address, and each address's generated message is valid") {
    REQUIRE(address_table().size() >= 16);
    for (const AddressSpec& spec : address_table()) {
        INFO(spec.address);
        for (const bool optional : {false, true}) {
            // With every optional argument too, when the address allows them all at once (a custom
            // liquid or material needs them together; a named DSD refuses gamma's).
            const auto bytes = encode_message(spec.address, test::valid_arguments(spec, optional));
            const ReceivedPacket p = receive(bytes);
            REQUIRE_FALSE(p.failed());
            REQUIRE(p.messages.size() == 1);
            if (!optional) CHECK_MESSAGE(p.messages[0].validation.ok, p.messages[0].validation.reason);
        }
        CHECK(find_address(spec.address) == &spec);
    }
}

TEST_CASE("every address refuses wrong types, NaN, Inf, huge, negative and out-of-range values, overlong strings, "
          "missing and extra arguments, with a reason, and builds nothing") {
    std::size_t cases = 0;
    for (const AddressSpec& spec : address_table()) {
        for (const test::BadCase& c : test::bad_cases(spec)) {
            INFO(spec.address << " " << c.what);
            const ReceivedPacket p = receive(encode_message(spec.address, c.args));
            REQUIRE_FALSE(p.failed());
            REQUIRE(p.messages.size() == 1);
            const Validation& v = p.messages[0].validation;
            ++cases;
            if (c.refused_by_scene) {
                // Passed on to the scene edit, whose validate_scene refuses it (the UDP test sees the /fail).
                if (v.ok) CHECK(v.request.action == Action::edit_scene);
                continue;
            }
            CHECK_FALSE(v.ok);
            CHECK_FALSE(v.reason.empty());
            CHECK(builds_nothing(v.request));
        }
    }
    MESSAGE(cases << " bad messages over " << address_table().size() << " addresses");
    CHECK(cases > 20 * address_table().size());
}

TEST_CASE("the reason names the argument and its unit for a value out of range") {
    const AddressSpec* spec = find_address("/drop");
    REQUIRE(spec);
    auto args = test::valid_arguments(*spec);
    args[1] = test::double_argument(25.0);
    const ReceivedPacket p = receive(encode_message("/drop", args));
    REQUIRE(p.messages.size() == 1);
    CHECK(p.messages[0].validation.reason == "argument 2 speed (m/s): 25 is outside 0..20");
}

TEST_CASE("malformed packets and bundles deeper than the bound are refused whole, with a reason and the address") {
    for (const test::BadPacket& b : test::bad_packets()) {
        INFO(b.what);
        const ReceivedPacket p = receive(b.bytes);
        CHECK(p.failed());
        CHECK(p.messages.empty());
    }
    // The address a /fail names: the bundle, or the message's own address (at most 64 characters).
    const auto deep = test::nested_bundle(max_bundle_depth + 1, encode_message("/status", {}));
    CHECK(receive(deep).fail_address == "#bundle");
    CHECK(receive(deep).fail_reason == "bundles nested deeper than 8");
    auto cut = encode_message("/rain/rate", {OscArgument::from_float(1.0f)});
    cut.resize(cut.size() - 4);
    CHECK(receive(cut).fail_address == "/rain/rate");
    const std::string long_address = "/" + std::string(100, 'a');
    auto long_cut = encode_message(long_address, {OscArgument::from_float(1.0f)});
    long_cut.resize(long_cut.size() - 4);
    CHECK(receive(long_cut).fail_address == long_address.substr(0, 64));
    CHECK(receive({}).fail_reason == "not an OSC message or bundle");
}

TEST_CASE("bundles nested to the bound decode, every message validated on its own") {
    const auto good = encode_message("/rain/rate", {OscArgument::from_float(10.0f)});
    const auto bad = encode_message("/rain/rate", {OscArgument::from_float(1000.0f)});
    const auto inner = encode_bundle(Timetag{}, {good, bad, encode_message("/nowhere", {})});
    const ReceivedPacket p = receive(test::nested_bundle(max_bundle_depth - 1, inner));
    REQUIRE_FALSE(p.failed());
    REQUIRE(p.messages.size() == 3);
    CHECK(p.messages[0].validation.ok);
    CHECK(p.messages[1].validation.reason == "argument 1 rate (mm/h): 1000 is outside 0..500");
    CHECK(p.messages[2].validation.reason == "unknown address");
}

TEST_CASE("a custom material's name fits a scene file (1-32 characters): the umbrella's material is saved") {
    const auto custom = [](const std::string& name) {
        return encode_message("/material/surface", {OscArgument::from_string("umbrella"), OscArgument::from_string(name),
                                                    OscArgument::from_float(0.1f), OscArgument::from_float(100),
                                                    OscArgument::from_float(1), OscArgument::from_float(1e-5f)});
    };
    CHECK(receive(custom(std::string(32, 'm'))).messages.at(0).validation.ok);
    CHECK(receive(custom(std::string(33, 'm'))).messages.at(0).validation.reason == "a material name has 1 to 32 characters");
}

TEST_CASE("scene_after: a listener carries the umbrella; the result validates or the daemon refuses the command") {
    const SceneDescription umbrella = *builtin_scene("umbrella");
    Command c;
    c.kind = CommandKind::listener;
    c.values[0] = 10.0;
    c.values[1] = -5.0;
    c.values[2] = 1.6;
    const SceneDescription moved = scene_after(umbrella, c);
    CHECK(moved.listener.x_m == 10.0);
    CHECK(moved.surfaces.at(0).x_m - moved.listener.x_m == umbrella.surfaces.at(0).x_m - umbrella.listener.x_m);
    CHECK(validate_scene(moved).empty());
    c.values[2] = 1000.0;   // the umbrella, 0.3 m above the ears, would be above 1000 m
    CHECK(validate_scene(scene_after(umbrella, c)).find("z 1000.3 m is outside -1000..1000") != std::string::npos);
    CHECK(changes_scene(CommandKind::listener));
    CHECK_FALSE(changes_scene(CommandKind::drop));
}
