// SPDX-License-Identifier: GPL-3.0-or-later
// The UDP backlog (server/osc/datagram_backlog.hpp): oldest first, bytes and senders intact through any
// number of wrap-arounds, bounded in count and in bytes (a full backlog refuses, never grows), and it
// tells whether a sender has anything waiting (so that its later queries keep their place).

#include "server/osc/datagram_backlog.hpp"

#include <doctest/doctest.h>

#include <deque>
#include <random>
#include <vector>

namespace {
using ameoto::DatagramBacklog;
using ameoto::Peer;

Peer sender(unsigned short port) { return Peer::over_udp({boost::asio::ip::make_address("127.0.0.1"), port}); }

std::vector<unsigned char> bytes_of(std::size_t size, unsigned seed) {
    std::vector<unsigned char> b(size);
    for (std::size_t i = 0; i < size; ++i) b[i] = static_cast<unsigned char>(seed * 31 + i * 7);
    return b;
}

struct Expected {
    std::vector<unsigned char> bytes;
    Peer from;
};
}  // namespace

TEST_CASE("backlog: what goes in comes out oldest first, bytes and sender intact, through many wrap-arounds") {
    // A reference queue (std::deque) beside the ring: random sizes (4..700 bytes) into 4 KiB force the
    // byte ring to wrap every few datagrams; random pushes and pops for 20 000 steps.
    DatagramBacklog backlog(32, 4096);
    std::deque<Expected> reference;
    std::mt19937 random(8);
    std::size_t wraps_seen = 0, refused = 0;
    const unsigned char* last_at = nullptr;
    for (unsigned step = 0; step < 20000; ++step) {
        if (random() % 2 == 0) {
            const auto b = bytes_of(4 + random() % 697, step);
            const Peer from = sender(static_cast<unsigned short>(1000 + random() % 5));
            if (backlog.push(b.data(), b.size(), from)) reference.push_back({b, from});
            else ++refused;
        } else if (!reference.empty()) {
            REQUIRE(!backlog.empty());
            const auto& d = backlog.front();
            REQUIRE(d.size == reference.front().bytes.size());
            CHECK(std::equal(d.data, d.data + d.size, reference.front().bytes.begin()));
            CHECK(d.sender == reference.front().from);
            if (last_at && d.data < last_at) ++wraps_seen;
            last_at = d.data;
            backlog.pop();
            reference.pop_front();
        }
        REQUIRE(backlog.size() == reference.size());
        REQUIRE(backlog.bytes() <= 4096);
    }
    CHECK(wraps_seen > 100);   // the ring really wrapped
    CHECK(refused > 0);        // and really filled
}

TEST_CASE("backlog: bounded by count and by bytes; a full backlog refuses and takes again once emptied") {
    DatagramBacklog by_count(4, 1 << 16);
    const auto small = bytes_of(16, 1);
    for (int i = 0; i < 4; ++i) REQUIRE(by_count.push(small.data(), small.size(), sender(1)));
    CHECK_FALSE(by_count.push(small.data(), small.size(), sender(1)));
    by_count.pop();
    CHECK(by_count.push(small.data(), small.size(), sender(1)));

    DatagramBacklog by_bytes(1000, 1024);
    const auto quarter = bytes_of(256, 2);
    for (int i = 0; i < 4; ++i) REQUIRE(by_bytes.push(quarter.data(), quarter.size(), sender(1)));
    CHECK_FALSE(by_bytes.push(small.data(), small.size(), sender(1)));   // not one more byte
    const auto too_large = bytes_of(1025, 3);
    by_bytes.pop();
    CHECK_FALSE(by_bytes.push(too_large.data(), too_large.size(), sender(1)));   // larger than the whole ring
    CHECK(by_bytes.push(quarter.data(), quarter.size(), sender(1)));              // where the first one was
    while (!by_bytes.empty()) by_bytes.pop();
    CHECK(by_bytes.bytes() == 0);
    const auto whole = bytes_of(1024, 4);
    CHECK(by_bytes.push(whole.data(), whole.size(), sender(1)));   // an empty ring takes its full size
}

TEST_CASE("backlog: holds_from tells whether a sender has anything waiting") {
    DatagramBacklog backlog(8, 1024);
    const auto b = bytes_of(12, 5);
    CHECK_FALSE(backlog.holds_from(sender(1)));
    backlog.push(b.data(), b.size(), sender(1));
    backlog.push(b.data(), b.size(), sender(2));
    CHECK(backlog.holds_from(sender(1)));
    CHECK(backlog.holds_from(sender(2)));
    CHECK_FALSE(backlog.holds_from(sender(3)));
    CHECK_FALSE(backlog.holds_from(Peer::over_tcp(1)));
    backlog.pop();
    CHECK_FALSE(backlog.holds_from(sender(1)));
    CHECK(backlog.holds_from(sender(2)));
}
