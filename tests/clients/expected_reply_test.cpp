// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/expected_reply.hpp"

#include <doctest/doctest.h>

#include "protocol/address_table.hpp"

using namespace ameoto::protocol;
using namespace ameoto::client;

namespace {
DecodedMessage message(std::string address, std::vector<OscArgument> args) {
    DecodedMessage m;
    m.address = std::move(address);
    m.args = std::move(args);
    return m;
}
}  // namespace

TEST_CASE("the known replies agree with the protocol table") {
    for (const AddressSpec& a : address_table()) {
        INFO(a.address);
        const std::string reply = a.reply;
        const auto expected = expected_reply(a.address);
        if (reply.empty()) {
            CHECK_FALSE(expected.has_value());
        } else {
            REQUIRE(expected.has_value());
            CHECK(*expected == reply.substr(0, reply.find(' ')));   // "/done /quit" -> "/done"
        }
    }
}

TEST_CASE("the wait ends at the settling reply and only there") {
    const std::vector<OscArgument> none;
    CHECK(ends_wait("/status", none, message("/status.reply", {OscArgument::from_float(1)})));
    CHECK(ends_wait("/sync", {OscArgument::from_int(7)}, message("/synced", {OscArgument::from_int(7)})));
    CHECK_FALSE(ends_wait("/sync", {OscArgument::from_int(7)}, message("/synced", {OscArgument::from_int(8)})));
    CHECK(ends_wait("/sync", {OscArgument::from_float(7)}, message("/synced", {OscArgument::from_int(7)})));
    CHECK(ends_wait("/quit", none, message("/done", {OscArgument::from_string("/quit")})));
    CHECK_FALSE(ends_wait("/quit", none, message("/done", {OscArgument::from_string("/other")})));

    // A refused message gets one /fail naming it, and nothing after.
    CHECK(ends_wait("/rain/rate", {OscArgument::from_int(900)}, message("/fail", fail_arguments("/rain/rate", "out of range"))));
    CHECK_FALSE(ends_wait("/rain/rate", {OscArgument::from_int(900)}, message("/fail", fail_arguments("/drop", "busy"))));
    // Accepted messages without a reply never end the wait early.
    CHECK_FALSE(ends_wait("/rain/rate", {OscArgument::from_int(30)}, message("/status.reply", {})));
    CHECK_FALSE(ends_wait("/status", none, message("/synced", {OscArgument::from_int(1)})));
    // A query is settled by ADDRESS.reply, and only its own.
    CHECK(ends_wait("/rain/rate", none, message("/rain/rate.reply", {OscArgument::from_float(2)})));
    CHECK(ends_wait("/material/surface", {OscArgument::from_string("umbrella")}, message("/material/surface.reply", {})));
    CHECK(ends_wait("/version", none, message("/version.reply", {})));
    CHECK_FALSE(ends_wait("/rain/rate", none, message("/rain/wind.reply", {})));
}
