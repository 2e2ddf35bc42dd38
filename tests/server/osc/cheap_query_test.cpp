// SPDX-License-Identifier: GPL-3.0-or-later
// Which datagrams a flooded server answers first (server/osc/cheap_query.hpp): the peek must agree
// with the full decode and validation, so that nothing is moved forward that the table would treat
// as a command, and nothing malformed is taken for a query.

#include "server/osc/cheap_query.hpp"

#include <doctest/doctest.h>

#include "protocol/receive.hpp"

namespace {
using ameoto::is_cheap_query;
using ameoto::is_status_request;
using ameoto::protocol::OscArgument;
using ameoto::protocol::encode_message;

bool cheap(const std::vector<unsigned char>& b) { return is_cheap_query(b.data(), b.size()); }
}  // namespace

TEST_CASE("cheap query: every address of the table asked with no value is cheap exactly when validation calls it status, version or a query") {
    ameoto::protocol::ProtocolContext context;
    context.on_surface = [](const std::string&, double, double) { return true; };
    int cheap_count = 0;
    for (const auto& spec : ameoto::protocol::address_table()) {
        const auto bytes = encode_message(spec.address, {});
        const auto received = ameoto::protocol::receive_packet(bytes.data(), bytes.size(), context);
        REQUIRE(received.messages.size() == 1);
        const auto& v = received.messages[0].validation;
        using ameoto::protocol::Action;
        const bool answered_at_once =
            v.ok && (v.request.action == Action::status || v.request.action == Action::version || v.request.action == Action::query);
        const std::string address = spec.address;
        CAPTURE(address);
        CHECK(cheap(bytes) == answered_at_once);
        cheap_count += cheap(bytes) ? 1 : 0;
    }
    CHECK(cheap_count >= 10);   // /status, /version and the queries
}

TEST_CASE("cheap query: with arguments, bundles and malformed bytes are not cheap; /status is recognised exactly") {
    CHECK(cheap(encode_message("/status", {})));
    CHECK(is_status_request(encode_message("/status", {}).data(), 12));
    CHECK_FALSE(is_status_request(encode_message("/version", {}).data(), 12));
    CHECK_FALSE(cheap(encode_message("/rain/rate", {OscArgument::from_float(30)})));   // a command
    CHECK_FALSE(cheap(encode_message("/status", {OscArgument::from_int(1)})));        // refused later, in its turn
    CHECK_FALSE(cheap(encode_message("/quit", {})));
    CHECK_FALSE(cheap(encode_message("/no/such/address", {})));
    const auto bundle = ameoto::protocol::encode_bundle({0, 1}, {encode_message("/status", {})});
    CHECK_FALSE(cheap(bundle));
    auto status = encode_message("/status", {});
    CHECK_FALSE(is_cheap_query(status.data(), status.size() - 4));   // no type tags
    CHECK_FALSE(is_cheap_query(status.data(), 7));                   // cut inside the address
    status[7] = 'x';                                                 // no NUL after the address
    CHECK_FALSE(cheap(status));
    CHECK_FALSE(is_cheap_query(nullptr, 0));
}
