// The shipped SuperCollider class clients/supercollider/Ameoto.sc, installed by its own install
// script into a temporary HOME's Extensions folder, run by the real sclang (supercollider-language,
// headless: no scsynth, no display) against the real ameotod.

#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "tests/real_clients/real_programs.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/temp_dir.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test;

TEST_CASE("SuperCollider: the install script puts Ameoto in the Extensions folder; sclang drives the server with it") {
    const auto sclang = find_program("sclang");
    if (!sclang) return skip_because_absent("sclang", "supercollider-language");
    TempDir home("ameoto-sclang-home");
    ChildOptions without_xdg;
    without_xdg.unset_env = {"XDG_*"};   // Platform.userExtensionDir then lies under $HOME

    const ProgramRun install =
        run_program({"sh", client_path("supercollider/install")}, 10s, {"HOME=" + home.path().string()}, without_xdg);
    INFO("install printed: " << install.out);
    REQUIRE(install.exit_code == 0);
    const auto installed = home.path() / ".local/share/SuperCollider/Extensions/ameoto/Ameoto.sc";
    REQUIRE(std::filesystem::exists(installed));

    DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0"});
    std::vector<std::string> env = {"HOME=" + home.path().string(), "QT_QPA_PLATFORM=offscreen",
                                    "AMEOTO_TEST_PORT=" + std::to_string(d.port())};
    // QtWebEngine (linked into sclang) refuses to start its sandbox as root unless told.
    if (geteuid() == 0) env.push_back("QTWEBENGINE_DISABLE_SANDBOX=1");
    const ProgramRun run = run_program({*sclang, test_file("supercollider/status_test.scd")}, 20s, env, without_xdg);
    INFO("sclang printed:\n" << run.out);
    CHECK_FALSE(run.timed_out);
    CHECK(run.out.find("sclang test: ok") != std::string::npos);
    REQUIRE(run.exit_code == 0);
    // The refused rate reached the class's onFail with the server's reason.
    CHECK(run.out.find("fail /rain/rate argument 1 rate (mm/h): 900 is outside 0..500") != std::string::npos);
    const auto status = name_value_lines(run.out, "status ");
    REQUIRE(status.size() == 13);
    CHECK(status.at("sample_rate_hz") == "48000.0");
    CHECK(status.at("block_size_frames") == "256");
    CHECK(std::stoi(status.at("active_drops_full")) >= 2);
    // sclang 3.13 cannot read the int64 of field 11: the class gives nil for it and the two after it
    // rather than wrong values; a sclang that can read it must give the server's backend.
    CHECK((status.at("backend") == "nil" || status.at("backend") == "null"));

    OscTestClient client(d.port());
    CHECK(settled_rain_rate(client) == doctest::Approx(12.0).epsilon(1e-6));
}
