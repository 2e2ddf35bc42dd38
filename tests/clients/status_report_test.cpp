// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/status_report.hpp"

#include <doctest/doctest.h>

#include <limits>

#include "protocol/osc_codec.hpp"

using namespace ameoto::protocol;
using namespace ameoto::client;

namespace {
// The reply as server/status.cpp builds it: "fffiiiiififfsfif".
DecodedMessage status_reply(std::vector<OscArgument> args = {}) {
    if (args.empty())
        args = {OscArgument::from_float(3.14f), OscArgument::from_float(12.0f), OscArgument::from_float(420.5f),
                OscArgument::from_int(17),      OscArgument::from_int(0),       OscArgument::from_int(0),
                OscArgument::from_int(2),       OscArgument::from_int(1),       OscArgument::from_float(48000.0f),
                OscArgument::from_int(256),     OscArgument::from_float(100000.5f), OscArgument::from_float(29.875f),
                OscArgument::from_string("null"), OscArgument::from_float(-12.25f), OscArgument::from_int(3),
                OscArgument::from_float(111.5f)};
    const auto bytes = encode_message("/status.reply", args);
    const DecodedPacket p = decode_packet(bytes.data(), bytes.size());
    REQUIRE(p.messages.size() == 1);
    return p.messages[0];
}
}  // namespace

TEST_CASE("the field table matches the server's type tags") {
    std::string tags;
    for (const auto& f : status_fields()) tags += f.kind == StatusKind::real ? 'f' : f.kind == StatusKind::integer ? 'i' : 's';
    CHECK(tags == "fffiiiiififfsfif");
    CHECK(status_reply().types == "fffiiiiififfsfif");
}

TEST_CASE("text output: one field per line with its name and unit") {
    const StatusReport r = parse_status_reply(status_reply());
    REQUIRE(r.error.empty());
    CHECK(format_status_text(r) ==
          "cpu average: 3.1 %\n"
          "cpu peak: 12 %\n"
          "drops per second: 420.5\n"
          "active drops, full tier: 17\n"
          "active drops, template tier: 0\n"
          "active drops, texture tier: 0\n"
          "xruns: 2\n"
          "late bundles: 1\n"
          "sample rate: 48000 Hz\n"
          "block size: 256 frames\n"
          "audio rendered: 100000.5 s\n"
          "rain rate: 29.88 mm/h\n"
          "backend: null\n"
          "audio clock against the wall: -12.2 ppm\n"
          "clipped samples: 3\n"
          "full scale: 111.5 dB SPL\n");
}

TEST_CASE("JSON output: one object, snake_case keys, floats as the server sent them") {
    const StatusReport r = parse_status_reply(status_reply());
    REQUIRE(r.error.empty());
    CHECK(format_status_json(r) ==
          R"({"cpu_average_percent": 3.14, "cpu_peak_percent": 12, "drops_per_second": 420.5, )"
          R"("active_drops_full": 17, "active_drops_template": 0, "active_drops_texture": 0, "xruns": 2, )"
          R"("late_bundles": 1, "sample_rate_hz": 48000, "block_size_frames": 256, "seconds_rendered": 100000.5, )"
          R"("rain_rate_mm_per_h": 29.875, "backend": "null", "clock_ppm": -12.25, "clipped_samples": 3, "full_scale_db_spl": 111.5})"
          "\n");
}

TEST_CASE("JSON stays valid for odd values") {
    auto args = status_reply().args;
    args[0] = OscArgument::from_float(std::numeric_limits<float>::quiet_NaN());
    args[12] = OscArgument::from_string("ja\"ck\n");
    const StatusReport r = parse_status_reply(status_reply(args));
    REQUIRE(r.error.empty());
    const std::string json = format_status_json(r);
    CHECK(json.starts_with(R"({"cpu_average_percent": null,)"));
    CHECK(json.find(R"("backend": "ja\"ck\u000a", "clock_ppm": -12.25,)") != std::string::npos);
}

TEST_CASE("numbers are read whatever their numeric tag; a wrong shape is refused") {
    auto args = status_reply().args;
    args[8] = OscArgument::from_int(44100);   // sample rate as i
    args[3] = OscArgument::from_float(5.0f);  // a count as f
    const StatusReport coerced = parse_status_reply(status_reply(args));
    REQUIRE(coerced.error.empty());
    CHECK(format_status_text(coerced).find("sample rate: 44100 Hz\n") != std::string::npos);
    CHECK(format_status_text(coerced).find("active drops, full tier: 5\n") != std::string::npos);

    auto short_args = status_reply().args;
    short_args.pop_back();
    const StatusReport too_short = parse_status_reply(status_reply(short_args));
    CHECK(too_short.values.empty());
    CHECK(too_short.error == "the server's /status.reply has 15 fields (,fffiiiiififfsfi), expected 16: a different version of ameotod?");

    auto text_for_number = status_reply().args;
    text_for_number[0] = OscArgument::from_string("busy");
    CHECK(parse_status_reply(status_reply(text_for_number)).error ==
          "the server's /status.reply field 1 (cpu average) is type 's', expected a number");

    auto extra = status_reply().args;
    extra.push_back(OscArgument::from_int(99));   // a newer server's extra field is ignored
    CHECK(parse_status_reply(status_reply(extra)).error.empty());
}
