// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/osc_codec.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

using namespace ameoto::protocol;

TEST_CASE("a message round-trips through encode and decode with every argument type") {
    const auto bytes = encode_message("/drop", {OscArgument::from_float(3.5f), OscArgument::from_int(-7),
                                                OscArgument::from_int64(1LL << 40), OscArgument::from_string("umbrella")});
    CHECK(bytes.size() % 4 == 0);
    const DecodedPacket p = decode_packet(bytes.data(), bytes.size());
    REQUIRE(p.error.empty());
    REQUIRE(p.messages.size() == 1);
    const auto& m = p.messages[0];
    CHECK(m.address == "/drop");
    CHECK(m.types == "fihs");
    CHECK(m.args[0].number == 3.5);
    CHECK(m.args[1].integer == -7);
    CHECK(m.args[2].integer == (1LL << 40));
    CHECK(m.args[3].text == "umbrella");
    CHECK(m.timetag.immediate());
    CHECK_FALSE(m.bundled);
}

TEST_CASE("bundles keep their timetag, nested bundles inherit or carry their own") {
    const Timetag outer{3900000000u, 0x80000000u};
    const Timetag inner_tt{3900000001u, 0};
    const auto m1 = encode_message("/sync", {OscArgument::from_int(1)});
    const auto inner_timed = encode_bundle(inner_tt, {encode_message("/sync", {OscArgument::from_int(2)})});
    const auto inner_now = encode_bundle(Timetag{}, {encode_message("/sync", {OscArgument::from_int(3)})});
    const auto bundle = encode_bundle(outer, {m1, inner_timed, inner_now});
    const DecodedPacket p = decode_packet(bundle.data(), bundle.size());
    REQUIRE(p.error.empty());
    REQUIRE(p.messages.size() == 3);
    CHECK(p.messages[0].timetag.seconds == outer.seconds);
    CHECK(p.messages[0].bundled);
    CHECK(p.messages[1].timetag.seconds == inner_tt.seconds);
    CHECK(p.messages[2].timetag.seconds == outer.seconds);   // "immediately" inside a timed bundle
}

TEST_CASE("timetags convert to and from Unix time to well under a microsecond") {
    const double t = 1795000000.123456;
    const Timetag tt = Timetag::from_unix_seconds(t);
    CHECK(std::abs(tt.to_unix_seconds() - t) < 1e-6);
    CHECK(tt.seconds == static_cast<std::uint32_t>(1795000000 + 2208988800ULL));
}

TEST_CASE("malformed packets are refused with a reason, never half-decoded") {
    SUBCASE("size not a multiple of 4") {
        const char junk[5] = {'/', 'a', 0, 0, 0};
        CHECK_FALSE(decode_packet(junk, 5).error.empty());
    }
    SUBCASE("not a message") {
        const char junk[8] = {'x', 'y', 0, 0, ',', 0, 0, 0};
        CHECK(decode_packet(junk, 8).error.find("not an OSC") != std::string::npos);
    }
    SUBCASE("type tags promise more data than there is") {
        auto bytes = encode_message("/rain/rate", {OscArgument::from_float(1.0f)});
        bytes.resize(bytes.size() - 4);
        CHECK_FALSE(decode_packet(bytes.data(), bytes.size()).error.empty());
    }
    SUBCASE("bundle element size runs past the end; the good first element is not kept") {
        auto bundle = encode_bundle(Timetag{}, {encode_message("/sync", {OscArgument::from_int(1)})});
        const unsigned char bad_size[4] = {0, 0, 1, 0};
        bundle.insert(bundle.end(), bad_size, bad_size + 4);
        const DecodedPacket p = decode_packet(bundle.data(), bundle.size());
        CHECK_FALSE(p.error.empty());
        CHECK(p.messages.empty());
    }
    SUBCASE("bundles nested too deep") {
        std::vector<unsigned char> b = encode_message("/sync", {OscArgument::from_int(1)});
        for (int i = 0; i < max_bundle_depth + 1; ++i) b = encode_bundle(Timetag{}, {b});
        CHECK(decode_packet(b.data(), b.size()).error.find("nested") != std::string::npos);
    }
    SUBCASE("empty packet") { CHECK_FALSE(decode_packet("", 0).error.empty()); }
}

TEST_CASE("encoding refuses a type it does not know instead of sending something else") {
    OscArgument blob;
    blob.type = 'b';
    CHECK_THROWS_AS(encode_message("/x", {blob}), std::invalid_argument);
    OscArgument symbol;
    symbol.type = 'S';
    symbol.text = "umbrella";
    const auto bytes = encode_message("/x", {symbol});
    const auto p = decode_packet(bytes.data(), bytes.size());
    REQUIRE(p.error.empty());
    CHECK(p.messages[0].types == "S");
    CHECK(p.messages[0].args[0].text == "umbrella");
}

TEST_CASE("an OSC float reads as the decimal its sender typed") {
    // 1.6f is 1.60000002384185791015625; the server takes it as 1.6 (the shortest text of that float),
    // so a saved scene shows what the user sent. Distinct floats stay distinct.
    const auto bytes = ameoto::protocol::encode_message("/x", {ameoto::protocol::OscArgument::from_float(1.6f),
                                                              ameoto::protocol::OscArgument::from_float(0.1f),
                                                              ameoto::protocol::OscArgument::from_float(16777217.0f),
                                                              ameoto::protocol::OscArgument::from_float(std::nextafter(1.6f, 2.0f))});
    const auto packet = ameoto::protocol::decode_packet(bytes.data(), bytes.size());
    REQUIRE(packet.error.empty());
    REQUIRE(packet.messages.size() == 1u);
    const auto& args = packet.messages[0].args;
    CHECK(args[0].number == 1.6);
    CHECK(args[1].number == 0.1);
    CHECK(static_cast<float>(args[2].number) == 16777217.0f);
    CHECK(args[3].number != args[0].number);   // the next float up is another decimal
    CHECK(static_cast<float>(args[3].number) == std::nextafter(1.6f, 2.0f));
    // An argument built in process reads as the one received: render score's text scores build theirs with
    // from_float, and their drops must land where ameotod puts the same message's (0.15, not 0.15000000596).
    const float sent[] = {1.6f, 0.1f, 16777217.0f, std::nextafter(1.6f, 2.0f)};
    for (std::size_t i = 0; i < args.size(); ++i) CHECK(ameoto::protocol::OscArgument::from_float(sent[i]).number == args[i].number);
    CHECK(ameoto::protocol::OscArgument::from_float(0.15f).number == 0.15);
}
