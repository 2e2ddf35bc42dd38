// SPDX-License-Identifier: GPL-3.0-or-later
// Score files for `ameoto render score`: the text format and scsynth's binary one.
#include "clients/ameoto/score_file.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <string>

using namespace ameoto::client;
using ameoto::protocol::OscArgument;

namespace {

std::string sized(const std::vector<unsigned char>& bundle) {
    const std::uint32_t n = static_cast<std::uint32_t>(bundle.size());
    std::string s{static_cast<char>(n >> 24), static_cast<char>(n >> 16), static_cast<char>(n >> 8), static_cast<char>(n)};
    return s + std::string(bundle.begin(), bundle.end());
}

}  // namespace

TEST_CASE("text score: times, addresses, inferred and quoted arguments, comments; sorted by time, stable") {
    const ScoreFile s = parse_score("# a score\n"
                                    "\n"
                                    "1.5 /rain/rate 20   # heavier\n"
                                    "0.25 /drop 3 0 0.15 0.05\n"
                                    "1.5 /lod 50 \"8\"\n"
                                    "2 /x \"two words \\\" and \\\\\" true\n",
                                    "s.txt");
    REQUIRE(s.error.empty());
    CHECK_FALSE(s.binary);
    REQUIRE(s.messages.size() == 4);
    CHECK(s.messages[0].seconds == 0.25);
    CHECK(s.messages[0].message.address == "/drop");
    CHECK(s.messages[0].message.types == "iiff");
    CHECK(s.messages[0].where == "s.txt:4");
    CHECK(s.messages[1].message.address == "/rain/rate");   // 1.5 as written first
    CHECK(s.messages[2].message.address == "/lod");
    CHECK(s.messages[2].message.types == "is");            // a quoted number is a string
    CHECK(s.messages[3].message.args[0].text == "two words \" and \\");
    CHECK(s.messages[3].message.types == "sT");
}

TEST_CASE("text score: what is not a score line is refused with its line") {
    CHECK(parse_score("0.5 /drop 3\nx /drop\n", "s.txt").error == "s.txt:2: 'x' is not a time (seconds from the start, a number >= 0)");
    CHECK(parse_score("-1 /drop\n", "s.txt").error.starts_with("s.txt:1: '-1' is not a time"));
    CHECK(parse_score("1 drop\n", "s.txt").error == "s.txt:1: an OSC address (starting with '/') must follow the time");
    CHECK(parse_score("1 /scene/load \"pond\n", "s.txt").error == "s.txt:1: a quoted string is not closed");
    CHECK(parse_score("1 /drop 3 0 0 0\n", "s.txt").messages.size() == 1);
}

TEST_CASE("binary score (Score.write): size-prefixed bundles, timetags in seconds from the start, nested bundles") {
    using ameoto::protocol::encode_bundle;
    using ameoto::protocol::encode_message;
    const auto drop = encode_message("/drop", {OscArgument::from_float(3.0f), OscArgument::from_float(0.0f), OscArgument::from_float(0.15f),
                                               OscArgument::from_float(0.05f)});
    const auto rate = encode_message("/rain/rate", {OscArgument::from_float(5.0f)});
    const std::string bytes = sized(encode_bundle(score_timetag(0.0), {rate})) +
                              sized(encode_bundle(score_timetag(2.25), {drop, encode_bundle(score_timetag(2.5), {drop})})) +
                              sized(encode_bundle(score_timetag(1.0), {drop}));
    const ScoreFile s = parse_score(bytes, "s.osc");
    REQUIRE(s.error.empty());
    CHECK(s.binary);
    REQUIRE(s.messages.size() == 4);
    CHECK(s.messages[0].seconds == 0.0);
    CHECK(s.messages[1].seconds == 1.0);
    CHECK(s.messages[1].where == "s.osc: bundle 3, message 1");
    CHECK(s.messages[2].seconds == 2.25);
    CHECK(s.messages[3].seconds == 2.5);   // exact: 0.5 and 0.25 are whole fractions of 2^32
    // 1/3 s: the fixed point's step is 2^-32 s (0.23 ns), far below a sample.
    CHECK(score_seconds(score_timetag(1.0 / 3.0)) == ameoto::test::relative(1.0 / 3.0).epsilon(1e-9));
    CHECK(parse_score(bytes.substr(0, bytes.size() - 3), "s.osc").error.starts_with("s.osc: bundle 3 (byte"));
}
