// SPDX-License-Identifier: GPL-3.0-or-later
// /reply/port's table (server/osc/reply_ports.hpp): a redirect keeps the sender's IP address and changes
// only the port, is keyed by address and port, is undone by restore, and is bounded: when full a new
// sender is refused and nobody already redirected loses their place.

#include "server/osc/reply_ports.hpp"

#include <doctest/doctest.h>

namespace {
using ameoto::ReplyPorts;
using Endpoint = ReplyPorts::Endpoint;

Endpoint at(const char* address, unsigned short port) { return Endpoint(boost::asio::ip::make_address(address), port); }
}  // namespace

TEST_CASE("a redirect sends to the sender's own IP address at the named port; restore undoes it") {
    ReplyPorts ports;
    const Endpoint max = at("192.168.1.20", 50123);   // [udpsend]'s ephemeral port
    CHECK(ports.destination(max) == max);
    CHECK(ports.port_of(max) == 0);
    REQUIRE(ports.redirect(max, 7771));
    CHECK(ports.destination(max) == at("192.168.1.20", 7771));
    CHECK(ports.port_of(max) == 7771);
    // Another port of the same machine is another sender; another machine is untouched.
    CHECK(ports.destination(at("192.168.1.20", 50124)) == at("192.168.1.20", 50124));
    CHECK(ports.destination(at("192.168.1.21", 50123)) == at("192.168.1.21", 50123));
    REQUIRE(ports.redirect(max, 9000));   // changing it again takes no new place
    CHECK(ports.port_of(max) == 9000);
    CHECK(ports.size() == 1);
    ports.restore(max);
    CHECK(ports.destination(max) == max);
    CHECK(ports.size() == 0);
    ports.restore(max);   // restoring twice is harmless
    CHECK(ports.size() == 0);
    // IPv6 senders keep their address and scope as well.
    REQUIRE(ports.redirect(at("::1", 40000), 7771));
    CHECK(ports.destination(at("::1", 40000)) == at("::1", 7771));
}

TEST_CASE("at capacity a new sender is refused, the redirected ones keep theirs, and a restore frees a place") {
    ReplyPorts ports;
    for (std::size_t i = 0; i < ReplyPorts::capacity; ++i)
        REQUIRE(ports.redirect(at("127.0.0.1", static_cast<unsigned short>(10000 + i)), 7771));
    CHECK(ports.size() == ReplyPorts::capacity);
    const Endpoint late = at("127.0.0.1", 60000);
    CHECK_FALSE(ports.redirect(late, 7771));
    CHECK(ports.destination(late) == late);
    CHECK(ports.size() == ReplyPorts::capacity);
    CHECK(ports.port_of(at("127.0.0.1", 10000)) == 7771);   // the first is still redirected
    CHECK(ports.redirect(at("127.0.0.1", 10000), 7772));      // one already in may still change its port
    ports.restore(at("127.0.0.1", 10001));
    CHECK(ports.redirect(late, 7771));
    CHECK(ports.destination(late) == at("127.0.0.1", 7771));
}
