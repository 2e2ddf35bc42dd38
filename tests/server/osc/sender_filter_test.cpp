// SPDX-License-Identifier: GPL-3.0-or-later
// --allow's CIDR matching: every boundary of a prefix, both families, and the refusals.

#include "server/osc/sender_filter.hpp"

#include <doctest/doctest.h>

namespace {
using ameoto::SenderFilter;

SenderFilter filter(const std::string& list) {
    std::string error;
    auto f = SenderFilter::parse(list, error);
    REQUIRE_MESSAGE(f, error);
    return *f;
}

bool allows(const SenderFilter& f, const std::string& address) { return f.allows(boost::asio::ip::make_address(address)); }

std::string refusal(const std::string& list) {
    std::string error;
    const auto f = SenderFilter::parse(list, error);
    CHECK_FALSE(f);
    return error;
}
}  // namespace

TEST_CASE("sender filter: no --allow lets everyone in") {
    const SenderFilter none;
    CHECK_FALSE(none.restricts());
    CHECK(allows(none, "192.0.2.1"));
    CHECK(allows(none, "2001:db8::1"));
}

TEST_CASE("sender filter: IPv4 networks match exactly their prefix") {
    const auto f = filter("10.0.0.0/8,192.168.1.0/24,127.0.0.2/32");
    CHECK(f.restricts());
    CHECK(allows(f, "10.0.0.0"));
    CHECK(allows(f, "10.255.255.255"));
    CHECK_FALSE(allows(f, "11.0.0.0"));
    CHECK_FALSE(allows(f, "9.255.255.255"));
    CHECK(allows(f, "192.168.1.77"));
    CHECK_FALSE(allows(f, "192.168.2.77"));
    CHECK(allows(f, "127.0.0.2"));
    CHECK_FALSE(allows(f, "127.0.0.1"));
    CHECK_FALSE(allows(f, "127.0.0.3"));
}

TEST_CASE("sender filter: prefixes that end inside a byte") {
    const auto f = filter("172.16.0.0/12");   // 172.16.0.0 .. 172.31.255.255
    CHECK(allows(f, "172.16.0.1"));
    CHECK(allows(f, "172.31.255.255"));
    CHECK_FALSE(allows(f, "172.32.0.0"));
    CHECK_FALSE(allows(f, "172.15.255.255"));
    const auto v6 = filter("2001:db8:8000::/33");
    CHECK(allows(v6, "2001:db8:8000::1"));
    CHECK(allows(v6, "2001:db8:ffff::1"));
    CHECK_FALSE(allows(v6, "2001:db8:7fff::1"));
}

TEST_CASE("sender filter: IPv6 networks, and IPv4 senders seen through an IPv6 socket") {
    const auto f = filter("::1/128, 2001:db8::/32, 127.0.0.0/8");
    CHECK(allows(f, "::1"));
    CHECK_FALSE(allows(f, "::2"));
    CHECK(allows(f, "2001:db8:1234::5"));
    CHECK_FALSE(allows(f, "2001:db9::5"));
    CHECK(allows(f, "::ffff:127.0.0.1"));     // IPv4-mapped: matched as IPv4
    CHECK_FALSE(allows(f, "::ffff:10.0.0.1"));
    const auto v4_only = filter("10.0.0.0/8");
    CHECK_FALSE(allows(v4_only, "::1"));      // families never match each other
    CHECK_FALSE(allows(filter("::/0"), "10.0.0.1"));
    CHECK(allows(filter("0.0.0.0/0"), "203.0.113.9"));
}

TEST_CASE("sender filter: a bare address is one host, and the list prints canonically") {
    const auto f = filter("127.0.0.1,::1");
    CHECK(f.text() == "127.0.0.1/32,::1/128");
    CHECK(allows(f, "127.0.0.1"));
    CHECK_FALSE(allows(f, "127.0.0.2"));
    CHECK(filter("2001:DB8:0:0::/64").text() == "2001:db8::/64");
}

TEST_CASE("sender filter: bad networks are refused with the offending text") {
    CHECK(refusal("10.0.0.0/33").find("0..32") != std::string::npos);
    CHECK(refusal("::1/129").find("0..128") != std::string::npos);
    CHECK(refusal("10.0.0.0/-1").find("prefix") != std::string::npos);
    CHECK(refusal("10.0.0.0/").find("prefix") != std::string::npos);
    CHECK(refusal("10.0.0.0/8x").find("prefix") != std::string::npos);
    CHECK(refusal("10.1.0.0/8").find("host bits") != std::string::npos);
    CHECK(refusal("example.org/8").find("'example.org/8' is not") != std::string::npos);
    CHECK(refusal("fe80::1%eth0/128").find("is not") != std::string::npos);
    CHECK(refusal("10.0.0.0/8,,::1").find("empty network") != std::string::npos);
    CHECK(refusal("").find("empty network") != std::string::npos);
    CHECK(refusal("10.0.0.0/8,").find("empty network") != std::string::npos);
}
