// SPDX-License-Identifier: GPL-3.0-or-later
// ameoto watch's formatting: /meter parsing, bars, the line format for pipes, the screen for terminals.
#include "clients/ameoto/watch_view.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "tests/support/osc_shorthand.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace ameoto::client;
using ameoto::protocol::DecodedMessage;
using ameoto::protocol::OscArgument;

namespace {

DecodedMessage sample_status_reply() {
    return message("/status.reply", {f(3.14), f(4.0), f(120), OscArgument::from_int(1), OscArgument::from_int(3),
                                     OscArgument::from_int(40), OscArgument::from_int(0), OscArgument::from_int(2), f(48000),
                                     OscArgument::from_int(256), f(2.0), f(2), OscArgument::from_string("null"),
                                     f(-3.5), OscArgument::from_int(0), f(110.5)});
}

}  // namespace

TEST_CASE("/meter parses into per-channel peak and RMS; a wrong shape is refused with the reason") {
    const auto m = parse_meter(message("/meter", {f(1.0), OscArgument::from_int(2), f(-12.5), f(-20), f(-120), f(-120)}));
    REQUIRE(m.error.empty());
    CHECK(m.seconds == 1.0);
    REQUIRE(m.peak_dbfs.size() == 2);
    CHECK(m.peak_dbfs[0] == doctest::Approx(-12.5));
    CHECK(m.rms_dbfs[0] == doctest::Approx(-20));
    CHECK(m.peak_dbfs[1] == -120);
    CHECK(parse_meter(message("/meter", {OscArgument::from_int(0), OscArgument::from_int(2), f(-1), f(-2)})).error.find("each of its 2") !=
          std::string::npos);
    CHECK_FALSE(parse_meter(message("/meter", {OscArgument::from_string("x")})).error.empty());
    CHECK_FALSE(parse_meter(message("/meter", {OscArgument::from_int(0), OscArgument::from_int(1), OscArgument::from_string("loud"), f(-2)}))
                    .error.empty());
    CHECK_FALSE(parse_meter(message("/meter", {OscArgument::from_int(0), OscArgument::from_int(-1)})).error.empty());
}

TEST_CASE("a bar spans -60..0 dBFS and never overflows its width") {
    CHECK(meter_bar(0.0, 10) == "[##########]");
    CHECK(meter_bar(-30.0, 10) == "[#####.....]");
    CHECK(meter_bar(-60.0, 10) == "[..........]");
    CHECK(meter_bar(-120.0, 10) == "[..........]");
    CHECK(meter_bar(+6.0, 10) == "[##########]");   // clipping shows full, not more
    CHECK(meter_bar(-std::numeric_limits<double>::infinity(), 4) == "[....]");
}

TEST_CASE("line format: one line per update, fields named, for pipes and logs") {
    const auto m = parse_meter(message("/meter", {f(0.1), OscArgument::from_int(2), f(-12.54), f(-20), f(-3), f(-9.96)}));
    CHECK(format_meter_line(m) == "meter t=0.100 1:-12.5/-20.0 2:-3.0/-10.0 dBFS peak/rms\n");
    // With the loudness (momentary, short-term, true peak) after the channels.
    const auto l = parse_meter(message("/meter", {f(0.1), OscArgument::from_int(1), f(-12.54), f(-20), f(-23.04), f(-22.96), f(-1.2)}));
    REQUIRE(l.error.empty());
    CHECK(format_meter_line(l) == "meter t=0.100 1:-12.5/-20.0 dBFS peak/rms M=-23.0 S=-23.0 LUFS TP=-1.2 dBTP\n");
    CHECK_FALSE(parse_meter(message("/meter", {f(0.1), OscArgument::from_int(1), f(-1), f(-2), f(-3)})).error.empty());
    const auto s = parse_status_reply(sample_status_reply());
    REQUIRE(s.error.empty());
    CHECK(format_status_line(s) ==
          "status cpu=3.1% peak=4.0% drops/s=120.0 full=1 template=3 texture=40 rain=2.00mm/h xruns=0 late=2 backend=null\n");
}

TEST_CASE("the terminal screen: load, rain and one bar per channel, a fixed number of lines") {
    WatchState state;
    state.target = "127.0.0.1:7770";
    const std::string empty = format_watch_screen(state);
    CHECK(empty.find("waiting for the first /status.reply") != std::string::npos);
    CHECK(empty.find("waiting for the first /meter") != std::string::npos);
    state.status = parse_status_reply(sample_status_reply());
    state.meter = parse_meter(message("/meter", {f(0.1), OscArgument::from_int(2), f(-12), f(-30), f(-6), f(-60)}));
    const std::string screen = format_watch_screen(state);
    CHECK(screen.starts_with("ameoto watch 127.0.0.1:7770  (Ctrl-C to quit)\n"));
    CHECK(screen.find("load  3.1 % average, 4.0 % peak   xruns 0   late bundles 2\n") != std::string::npos);
    CHECK(screen.find("rain  2.00 mm/h, 120.0 drops/s") != std::string::npos);
    CHECK(screen.find("2.0 s played, 0 dBFS = 110.50 dB SPL, 0 samples past full scale") != std::string::npos);
    CHECK(screen.find("ch 1  [" + std::string(20, '#') + std::string(20, '.') + "] rms -30.0  peak -12.0 dBFS\n") != std::string::npos);
    CHECK(screen.find("ch 2  [" + std::string(40, '.') + "] rms -60.0  peak -6.0 dBFS\n") != std::string::npos);
    // Redrawing in place moves up by the previous screen's lines: the shape must not change as values do.
    const auto lines = [](const std::string& t) { return std::count(t.begin(), t.end(), '\n'); };
    CHECK(lines(screen) == lines(empty) + 1);   // the one "waiting for /meter" line became two channels
}
