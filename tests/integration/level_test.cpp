// SPDX-License-Identifier: GPL-3.0-or-later
// Level and loudness against the real daemon over UDP (docs/loudness.md): /gain and /loudness set,
// queried and refused; the calibration in /status.reply and /loudness.reply; --level physical.

#include <doctest/doctest.h>
#include <signal.h>

#include <cmath>
#include <fstream>
#include <string>
#include <thread>

#include "engine/render/level_choice.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_shorthand.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/rt_report.hpp"

using namespace ameoto::test::osc_shorthand;
using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;
using Daemon = ameoto::test::DaemonProcess;

namespace {

constexpr double level_physical_full_scale = 133.9794;   // 20 log10(100 Pa / 20 uPa), dB SPL

ameoto::protocol::DecodedMessage ask_level(OscTestClient& c, const std::string& address) {
    auto r = c.request(address, {}, address + ".reply", 2s);
    REQUIRE_MESSAGE(r, "no " << address << ".reply");
    return *r;
}

}  // namespace

TEST_CASE("/gain and /loudness: set, queried, refused out of range with nothing changed; the calibration follows") {
    const std::string report = ameoto::test::temp_path("level-rt.txt");
    {
        Daemon d({"--backend", "null", "--output", "-", "--realtime", "--rain", "20", "--level", "auto"},
                 {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report});
        OscTestClient c(d.port());
        auto l = ask_level(c, "/loudness");
        REQUIRE(l.types == "sfffff");
        CHECK(l.args[0].text == "auto");
        CHECK(l.args[1].number == -23.0f);
        const double measured = l.args[2].number, level = l.args[3].number;
        CHECK(measured < -23.0);   // the umbrella's 2 mm/h at 1.0 = 100 Pa is quieter than the target
        // The difference, and what makes up for the limiter (the umbrella in air is peaky: level_choice.hpp).
        CHECK(level >= -23.0 - measured - 1e-4);
        CHECK(level <= -23.0 - measured + ameoto::max_limiter_share_db + 1e-4);
        CHECK(l.args[4].number == 0.0f);
        CHECK(l.args[5].number == doctest::Approx(level_physical_full_scale - level).epsilon(1e-5));
        CHECK(ask_level(c, "/gain").args[0].number == 0.0f);

        c.send("/gain", {f(-6.0)});
        CHECK(ask_level(c, "/gain").args[0].number == -6.0f);
        auto fail = c.request("/gain", {f(90.0)}, "/fail", 2s);
        REQUIRE(fail);
        CHECK(fail->args[0].text == "/gain");
        CHECK(fail->args[1].text.find("outside -80..80") != std::string::npos);
        CHECK(ask_level(c, "/gain").args[0].number == -6.0f);

        c.send("/loudness", {f(-18.0)});
        l = ask_level(c, "/loudness");
        CHECK(l.args[1].number == -18.0f);   // the target is in force at once
        // The gain follows once the worker has found it through the limiter (level_choice.hpp: tens of ms).
        for (int k = 0; k < 100 && l.args[3].number == level; ++k) {
            std::this_thread::sleep_for(20ms);
            l = ask_level(c, "/loudness");
        }
        CHECK(l.args[2].number == doctest::Approx(measured).epsilon(1e-6));        // not measured again
        // Moved by the difference, and by what makes up for the limiter at the louder target (at most 12 dB).
        const double moved = l.args[3].number - level;
        MESSAGE("/loudness -23 -> -18 LUFS moved the level gain by " << moved << " dB");
        CHECK(moved >= 5.0 - 1e-4);
        CHECK(moved <= 5.0 + ameoto::max_limiter_share_db + 1e-4);
        CHECK(l.args[5].number == doctest::Approx(level_physical_full_scale - level - moved + 6.0).epsilon(1e-5));
        REQUIRE(c.request("/loudness", {f(0.0)}, "/fail", 2s));
        CHECK(ask_level(c, "/loudness").args[1].number == -18.0f);

        // /status.reply field 15 says the same once the audio thread has applied both (field 14: clipped).
        REQUIRE(c.request("/sync", {i(1)}, "/synced", 2s));
        const auto status = c.request("/status", {}, "/status.reply", 2s);
        REQUIRE(status);
        CHECK(status->args[15].number == doctest::Approx(level_physical_full_scale - level - moved + 6.0).epsilon(1e-5));
        CHECK(status->args[14].integer == 0);   // 20 mm/h, 20 dB over the target's rain: the limiter holds it
        for (int k = 0; k < 20; ++k) c.send("/gain", {f(k % 2 ? 12.0 : -12.0)});   // ramps, one after another
        REQUIRE(c.request("/sync", {i(2)}, "/synced", 2s));
        std::this_thread::sleep_for(200ms);
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    // The gain ramps and the limiter ran on the audio thread without allocating, locking or logging.
    const auto rt = ameoto::test::read_rt_report(report);
    INFO(rt.text);
    CHECK(rt.no_violations());
    CHECK(rt.probed());
}

TEST_CASE("/loudness while a scene load is measured: the new scene plays at the new target") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0", "--level", "auto"});
    OscTestClient c(d.port());
    // The worker renders 3 s of the pond to measure it (about a second of CPU): the target changes meanwhile.
    c.send("/scene/load", {s("pond")});
    c.send("/loudness", {f(-30.0)});
    REQUIRE(c.wait_for("/done", 60s));
    const auto l = ask_level(c, "/loudness");
    CHECK(l.args[1].number == -30.0f);
    CHECK(l.args[2].number < -90.0);   // the pond's 1.5 mm/h at 1.0 = 100 Pa (about -105 LUFS)
    CHECK(l.args[3].number == doctest::Approx(-30.0 - l.args[2].number).epsilon(1e-5));   // not -23 - measured
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
}

TEST_CASE("--level physical: 1.0 = 100 Pa, no loudness target; --gain sets the gain") {
    Daemon d({"--backend", "null", "--output", "-", "--level", "physical", "--gain", "20"});
    OscTestClient c(d.port());
    const auto l = ask_level(c, "/loudness");
    CHECK(l.args[0].text == "physical");
    CHECK(l.args[3].number == 0.0f);
    CHECK(l.args[4].number == 20.0f);
    CHECK(l.args[5].number == doctest::Approx(level_physical_full_scale - 20.0).epsilon(1e-5));
    const auto fail = c.request("/loudness", {f(-20.0)}, "/fail", 2s);
    REQUIRE(fail);
    CHECK(fail->args[1].text.find("physical") != std::string::npos);
    CHECK(ask_level(c, "/loudness").args[1].number == -23.0f);
}
