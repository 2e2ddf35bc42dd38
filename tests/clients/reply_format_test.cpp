// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/reply_format.hpp"

#include <doctest/doctest.h>

#include "protocol/address_table.hpp"

using namespace ameoto::protocol;
using ameoto::client::format_message;

namespace {
// Through the real codec, as a reply off the wire would come.
DecodedMessage round_trip(const std::string& address, const std::vector<OscArgument>& args) {
    const auto bytes = encode_message(address, args);
    const DecodedPacket p = decode_packet(bytes.data(), bytes.size());
    REQUIRE(p.error.empty());
    REQUIRE(p.messages.size() == 1);
    return p.messages[0];
}
}  // namespace

TEST_CASE("a /fail prints like oscdump, strings quoted") {
    const auto m = round_trip("/fail", fail_arguments("/rain/rate", "argument 1 rate (mm/h): 900 is outside 0..500"));
    CHECK(format_message(m) == R"(/fail "/rain/rate" "argument 1 rate (mm/h): 900 is outside 0..500")");
}

TEST_CASE("numbers keep their type visible: floats always show a point") {
    const auto m = round_trip("/status.reply", {OscArgument::from_float(3.1f), OscArgument::from_float(48000.0f),
                                                OscArgument::from_int(256), OscArgument::from_int64(9000000000LL),
                                                OscArgument::from_float(-0.5f), OscArgument::from_float(1e20f)});
    CHECK(format_message(m) == "/status.reply 3.1 48000.0 256 9000000000 -0.5 1e+20");
}

TEST_CASE("other types and awkward strings") {
    OscArgument t, f, n, d;
    t.type = 'T';
    f.type = 'F';
    n.type = 'N';
    d.type = 'd';
    d.number = 0.25;
    const auto m = round_trip("/x", {t, f, n, d, OscArgument::from_string("say \"hi\"\n\\ok\x01")});
    CHECK(format_message(m) == R"(/x true false nil 0.25 "say \"hi\"\n\\ok\x01")");
    CHECK(format_message(round_trip("/done", {})) == "/done");
}
