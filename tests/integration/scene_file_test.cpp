// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod --scene FILE.scene: the real daemon started on a scene file given by its path (the command
// line is trusted; over OSC, /scene/load takes names only), and stopped at once, with the file, line
// and key, when that file is missing or malformed.

#include <doctest/doctest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_shorthand.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/temp_dir.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test::osc_shorthand;

namespace {

// A first scene that differs from every built-in one in each field a query answers.
constexpr const char* scene_file_text =
    "ameoto-scene 1\n"
    "# written by scene_file_test\n"
    "name from-a-file\n"
    "rain rate=7.5 wind=3 direction=90 gust=0.2\n"
    "surface brolly kind=umbrella material=vinyl size=1.1 z=1.9 panels=6\n"
    "surface roof kind=plate material=tin size=1x0.6 x=-3 y=2 z=3\n";

// ameotod that cannot start: its exit status (-1 when it did not end in time) and everything it said.
struct FailedStart {
    int status = -1;
    std::string output;
};

FailedStart start_with_scene(const std::string& scene) {
    ameoto::test::ChildProcess p({ameoto::test::ameotod, "--backend", "null", "--output", "-", "--port", "0", "--scene", scene});
    FailedStart f;
    f.status = p.wait(20s);
    f.output = p.output();
    return f;
}

}  // namespace

TEST_CASE("ameotod --scene PATH.scene plays that file's scene; the queries answer it; OSC still takes names only") {
    ameoto::test::TempDir dir("ameoto-scene-file");
    const std::string path = (dir.path() / "my.scene").string();
    std::ofstream(path) << scene_file_text;
    ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--scene", path});
    ameoto::test::OscTestClient c(d.port());

    const auto scene = c.request("/scene", {}, "/scene.reply", 2s);
    REQUIRE(scene);
    REQUIRE(scene->args.size() == 1);
    CHECK(scene->args[0].text == "from-a-file");
    const auto rate = c.request("/rain/rate", {}, "/rain/rate.reply", 2s);
    REQUIRE(rate);
    CHECK(rate->args[0].number == doctest::Approx(7.5));
    const auto wind = c.request("/rain/wind", {}, "/rain/wind.reply", 2s);
    REQUIRE(wind);
    CHECK(wind->args[0].number == doctest::Approx(3.0));
    CHECK(wind->args[1].number == doctest::Approx(90.0));
    const auto surfaces = c.request("/surfaces", {}, "/surfaces.reply", 2s);
    REQUIRE(surfaces);
    REQUIRE(surfaces->args.size() == 2);
    CHECK(surfaces->args[0].text == "brolly");
    CHECK(surfaces->args[1].text == "roof");
    const auto material = c.request("/material/surface", {s("brolly")}, "/material/surface.reply", 2s);
    REQUIRE(material);
    CHECK(material->args[1].text == "vinyl");
    // /status: the engine plays the file's rain (field 12, mm/h).
    const auto status = c.request("/status", {}, "/status.reply", 2s);
    REQUIRE(status);
    CHECK(status->args[11].number == doctest::Approx(7.5));
    // The same path over OSC is no name: refused, and the scene stays.
    const auto refused = c.request("/scene/load", {s(path)}, "/fail", 2s);
    REQUIRE(refused);
    CHECK(refused->args[0].text == "/scene/load");
    const auto still = c.request("/scene", {}, "/scene.reply", 2s);
    REQUIRE(still);
    CHECK(still->args[0].text == "from-a-file");
    CHECK(d.process().output().find("ameotod: scene from-a-file\n") != std::string::npos);
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
}

TEST_CASE("ameotod --scene with a missing or malformed file stops before it listens: exit 1, the file, line and key") {
    ameoto::test::TempDir dir("ameoto-scene-file");
    SUBCASE("missing") {
        const std::string path = (dir.path() / "nowhere.scene").string();
        const FailedStart f = start_with_scene(path);
        INFO(f.output);
        CHECK(f.status == 1);
        CHECK(f.output.find("ameotod: --scene: cannot open " + path + ": No such file or directory\n") != std::string::npos);
        CHECK(f.output.find("listening on") == std::string::npos);
    }
    SUBCASE("a value out of range") {
        const std::string path = (dir.path() / "bad-rate.scene").string();
        std::ofstream(path) << "ameoto-scene 1\nname bad\nrain rate=900\n";
        const FailedStart f = start_with_scene(path);
        INFO(f.output);
        CHECK(f.status == 1);
        CHECK(f.output.find("ameotod: --scene: " + path + ":3: rate: 900 mm/h is outside 0..500\n") != std::string::npos);
        CHECK(f.output.find("listening on") == std::string::npos);
    }
    SUBCASE("an unknown key") {
        const std::string path = (dir.path() / "bad-key.scene").string();
        std::ofstream(path) << "ameoto-scene 1\nsurface brolly kind=umbrella material=vinyl size=1 colour=red\n";
        const FailedStart f = start_with_scene(path);
        INFO(f.output);
        CHECK(f.status == 1);
        CHECK(f.output.find("ameotod: --scene: " + path + ":2: colour: ") != std::string::npos);
    }
    SUBCASE("a folder") {
        const std::string path = (dir.path() / "folder.scene").string();
        std::filesystem::create_directory(path);
        const FailedStart f = start_with_scene(path);
        INFO(f.output);
        CHECK(f.status == 1);
        CHECK(f.output.find("is not a regular file") != std::string::npos);
    }
    SUBCASE("neither a name nor a .scene file: a usage error") {
        const FailedStart f = start_with_scene((dir.path() / "my-rain").string());
        INFO(f.output);
        CHECK(f.status == 2);
        CHECK(f.output.find("is neither a scene name") != std::string::npos);
    }
}
