// SPDX-License-Identifier: GPL-3.0-or-later
// /canopy/impact end to end: the real daemon over loopback UDP. The scene is rebuilt off the audio thread
// with the chosen exchange (/done once it plays), the query answers it, /scene/save keeps it (the
// umbrella's impact= key), and bad input or a scene without an umbrella gets /fail and changes nothing.

#include <doctest/doctest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;
using Daemon = ameoto::test::DaemonProcess;

TEST_CASE("/canopy/impact over UDP: set, query, save, refuse; nothing changes on a refusal") {
    const std::string folder = ameoto::test::temp_path("impact-scenes");
    std::filesystem::create_directories(folder);
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--scene-dir", folder});
    OscTestClient client(d.port());
    auto s = [](const char* v) { return OscArgument::from_string(v); };
    auto impact = [&] {
        const auto q = client.request("/canopy/impact", {}, "/canopy/impact.reply", 2s);
        REQUIRE(q);
        REQUIRE(q->types == "s");
        return q->args[0].text;
    };
    CHECK(impact() == "wet");   // the default: a liquid's impulse
    const auto done = client.request("/canopy/impact", {s("seed")}, "/done", 20s);
    REQUIRE(done);
    CHECK(done->args[0].text == "/canopy/impact");
    CHECK(impact() == "seed");
    // A /drop on the rebuilt canopy is played (the /sync behind it answers).
    client.send("/drop", {OscArgument::from_float(3.0f), OscArgument::from_float(0.0f), OscArgument::from_float(0.2f),
                          OscArgument::from_float(0.05f)});
    REQUIRE(client.request("/sync", {OscArgument::from_int(3)}, "/synced", 2s));
    // Saved with the scene.
    REQUIRE(client.request("/scene/save", {s("seeded")}, "/done", 5s));
    std::ifstream in(folder + "/seeded.scene");
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    CHECK(text.find(" impact=seed") != std::string::npos);
    // Another name: refused with the reason, the exchange unchanged.
    auto refused = client.request("/canopy/impact", {s("elastic")}, "/fail", 2s);
    REQUIRE(refused);
    CHECK(refused->args[0].text == "/canopy/impact");
    CHECK(refused->args[1].text.find("'elastic' is not wet or seed") != std::string::npos);
    CHECK(impact() == "seed");
    // A scene without an umbrella: refused, and the query says wet (there is no canopy to strike).
    REQUIRE(client.request("/scene/load", {s("pond")}, "/done", 20s));
    refused = client.request("/canopy/impact", {s("wet")}, "/fail", 5s);
    REQUIRE(refused);
    CHECK(refused->args[1].text.find("no umbrella") != std::string::npos);
    CHECK(impact() == "wet");
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
}
