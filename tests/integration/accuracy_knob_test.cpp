// SPDX-License-Identifier: GPL-3.0-or-later
// The accuracy knob end to end: the real daemon over loopback UDP. /accuracy sets the budget (the
// scene is rebuilt off the audio thread with the chosen method, /done once it plays), /accuracy with
// no arguments answers /accuracy.reply with the choice, bad input gets /fail and changes nothing,
// /scene/save keeps the budget (a version 2 file), and the audio thread never breaks its contract.

#include <doctest/doctest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "engine/core/method_choice.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/rt_report.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;
using Daemon = ameoto::test::DaemonProcess;

namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("/accuracy over UDP: set, query, refuse, save; no real-time violations") {
    const std::string report = ameoto::test::temp_path("accuracy-rt.txt");
    const std::string folder = ameoto::test::temp_path("accuracy-scenes");
    std::filesystem::create_directories(folder);
    {
        Daemon d({"--backend", "null", "--output", "-", "--realtime", "--scene-dir", folder},
                 {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report});
        OscTestClient client(d.port());
        auto s = [](const char* v) { return OscArgument::from_string(v); };
        auto f = [](double v) { return OscArgument::from_float(static_cast<float>(v)); };
        // No budget yet: the default method.
        auto q = client.request("/accuracy", {}, "/accuracy.reply", 2s);
        REQUIRE(q);
        CHECK(q->types == "sfsiis");
        CHECK(q->args[0].text == "off");
        CHECK(q->args[2].text == "explicit Verlet 1x");
        // A budget in dB: the reply names what the engine's table picks for it.
        const ameoto::MethodChoice expected = ameoto::choose_method({ameoto::AccuracyMeasure::decibels, 1.0});
        const auto done = client.request("/accuracy", {s("db"), f(1.0)}, "/done", 10s);
        REQUIRE(done);
        CHECK(done->args[0].text == "/accuracy");
        q = client.request("/accuracy", {}, "/accuracy.reply", 2s);
        REQUIRE(q);
        CHECK(q->args[0].text == "db");
        CHECK(q->args[1].number == doctest::Approx(1.0));
        CHECK(q->args[2].text == ameoto::method_label(expected.method.setting));
        CHECK(q->args[4].integer == expected.method.setting.modes);
        CHECK(q->args[5].text == expected.reason);
        // A /drop on the rebuilt canopy is heard (the /sync behind it answers).
        client.send("/drop", {f(3), f(0), f(0.2), f(0.05)});
        REQUIRE(client.request("/sync", {OscArgument::from_int(3)}, "/synced", 2s));
        // Refusals name the problem and change nothing.
        struct Bad {
            std::vector<OscArgument> args;
            const char* needle;
        };
        const std::vector<Bad> bad = {{{s("cents")}, "give the budget"},
                                      {{s("hertz"), f(1)}, "not one of cents, db, off"},
                                      {{s("db"), f(100)}, "0.001 to 60 dB"},
                                      {{s("cents"), f(0)}, "outside"},
                                      {{s("off"), f(1)}, "'off' takes no budget"},
                                      {{f(5)}, "expected a string"}};
        for (const Bad& b : bad) {
            CAPTURE(b.needle);
            const auto refused = client.request("/accuracy", b.args, "/fail", 2s);
            REQUIRE(refused);
            CHECK(refused->args[0].text == "/accuracy");
            CHECK(refused->args[1].text.find(b.needle) != std::string::npos);
        }
        q = client.request("/accuracy", {}, "/accuracy.reply", 2s);
        REQUIRE(q);
        CHECK(q->args[0].text == "db");
        // The budget is part of the scene: saved as a version 2 file.
        REQUIRE(client.request("/scene/save", {s("careful")}, "/done", 5s));
        const std::string text = read_file(folder + "/careful.scene");
        CHECK(text.rfind("ameoto-scene 2\n", 0) == 0);
        CHECK(text.find("accuracy db=1\n") != std::string::npos);
        // Off again: back to the default method.
        REQUIRE(client.request("/accuracy", {s("off")}, "/done", 10s));
        q = client.request("/accuracy", {}, "/accuracy.reply", 2s);
        REQUIRE(q);
        CHECK(q->args[0].text == "off");
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    const auto rt = ameoto::test::read_rt_report(report);
    INFO(rt.text);
    CHECK(rt.no_violations());
}
