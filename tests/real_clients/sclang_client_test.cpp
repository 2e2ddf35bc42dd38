// SPDX-License-Identifier: GPL-3.0-or-later
// The shipped SuperCollider class clients/supercollider/Ameoto.sc, installed by its own install
// script into a temporary HOME's Extensions folder, run by the real sclang (supercollider-language,
// headless: no scsynth, no display) against the real ameotod.

#include <doctest/doctest.h>
#include <unistd.h>

#include <signal.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>

#include "protocol/address_table.hpp"
#include "tests/real_clients/drop_onsets.hpp"
#include "tests/real_clients/free_udp_port.hpp"
#include "tests/real_clients/real_programs.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test;

namespace {

// sclang headless: no display (offscreen Qt), no scsynth, HOME where the class was installed.
ProgramRun run_sclang(const std::string& sclang, const TempDir& home, int port, const std::string& script,
                      const ChildOptions& options, const std::vector<std::string>& more_env = {}) {
    std::vector<std::string> env = {"HOME=" + home.path().string(), "QT_QPA_PLATFORM=offscreen",
                                    "AMEOTO_TEST_PORT=" + std::to_string(port),
                                    // how long a script waits for /synced or a reply: 3 s, stretched with every
                                    // other wait under the sanitizers (timing_scale.hpp)
                                    "AMEOTO_TEST_SYNC_WAIT=" + std::to_string(3 * timing_scale())};
    // QtWebEngine (linked into sclang) refuses to start its sandbox as root unless told.
    if (geteuid() == 0) env.push_back("QTWEBENGINE_DISABLE_SANDBOX=1");
    env.insert(env.end(), more_env.begin(), more_env.end());
    return run_program({sclang, test_file(script)}, 20s, env, options);
}

ChildOptions without_xdg() {
    ChildOptions o;
    o.unset_env = {"XDG_*"};   // Platform.userExtensionDir then lies under $HOME
    return o;
}

void install_class(const TempDir& home) {
    const ProgramRun install =
        run_program({"sh", client_path("supercollider/install")}, 10s, {"HOME=" + home.path().string()}, without_xdg());
    INFO("install printed: " << install.out);
    REQUIRE(install.exit_code == 0);
    REQUIRE(std::filesystem::exists(home.path() / ".local/share/SuperCollider/Extensions/ameoto/Ameoto.sc"));
}

}  // namespace

TEST_CASE("SuperCollider: the install script puts Ameoto in the Extensions folder; sclang drives the server with it") {
    const auto sclang = find_program("sclang");
    if (!sclang) return skip_because_absent("sclang", "supercollider-language");
    TempDir home("ameoto-sclang-home");
    install_class(home);
    DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0"}, {}, DaemonOptions::patient());
    const ProgramRun run = run_sclang(*sclang, home, d.port(), "supercollider/status_test.scd", without_xdg());
    INFO("sclang printed:\n" << run.out);
    CHECK_FALSE(run.timed_out);
    CHECK(run.out.find("sclang test: ok") != std::string::npos);
    REQUIRE(run.exit_code == 0);
    // The refused rate reached the class's onFail with the server's reason.
    CHECK(run.out.find("fail /rain/rate argument 1 rate (mm/h): 900 is outside 0..500") != std::string::npos);
    const auto status = name_value_lines(run.out, "status ");
    REQUIRE(status.size() == 16);
    CHECK(status.at("sample_rate_hz") == "48000.0");
    CHECK(status.at("block_size_frames") == "256");
    // The two drops the script sent are lattice drops, still sounding when it asked (right after
    // /synced), when the callback has time for them: under the sanitizers the governor sheds them.
    AMEOTO_CHECK_UNLESS_SANITIZED(std::stoi(status.at("active_drops_full")) >= 2);
    // Every field is f, i or s (protocol version 2), all of which sclang reads.
    CHECK(status.at("backend") == "null");
    CHECK(std::stod(status.at("seconds_rendered")) > 0.0);

    OscTestClient client(d.port());
    CHECK(settled_rain_rate(client) == doctest::Approx(12.0).epsilon(1e-6));
}

TEST_CASE("SuperCollider: Ameoto.dropAt's bundles sound 0.25 s apart to +/- 1 sample, none late") {
    const auto sclang = find_program("sclang");
    if (!sclang) return skip_because_absent("sclang", "supercollider-language");
    TempDir home("ameoto-sclang-home");
    install_class(home);
    const std::string wav = temp_path("sclang-bundles.wav");
    ProgramRun run;
    {
        DaemonProcess d({"--backend", "null", "--output", wav, "--realtime", "--rain", "0", "--scene", sharp_onset_scene()}, {}, DaemonOptions::patient());
        run = run_sclang(*sclang, home, d.port(), "supercollider/timing_test.scd", without_xdg());
        OscTestClient client(d.port());
        const auto status = client.request("/status", {}, "/status.reply", 2s);
        REQUIRE(status);
        AMEOTO_CHECK_UNLESS_SANITIZED(status->args[7].integer == 0);   // late bundles: none, the timetags were ahead
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    INFO("sclang printed:\n" << run.out);
    REQUIRE(run.exit_code == 0);
    const WavData w = read_wav(wav);
    REQUIRE_MESSAGE(w.ok, w.error);
    if (stop_here_if_sanitized("the null backend's real-time schedule: the audio runs slower than real time, so bundles come late"))
        return;
    const std::vector<long long> onsets = drop_onsets(w, 0.02f, 2000);
    REQUIRE(onsets.size() == 3);
    // The three timetags are one logical time plus 0.5, 0.75 and 1 s: 12000 frames apart at 48 kHz,
    // +/- 1 for the server's rounding of each (AudioBridge::frame_for).
    CHECK(std::llabs(onsets[1] - onsets[0] - 12000) <= 1);
    CHECK(std::llabs(onsets[2] - onsets[1] - 12000) <= 1);
}

TEST_CASE("SuperCollider: every Ameoto method sends its documented address and arguments (oscdump)") {
    const auto sclang = find_program("sclang");
    const auto oscdump = find_program("oscdump");
    if (!sclang) return skip_because_absent("sclang", "supercollider-language");
    if (!oscdump) return skip_because_absent("oscdump", "liblo-tools");
    TempDir home("ameoto-sclang-home");
    install_class(home);
    const int port = free_udp_port();
    ChildProcess dump({*oscdump, "-L", std::to_string(port)});
    std::this_thread::sleep_for(300ms);   // oscdump binds its port before sclang (slower to start) sends
    const ProgramRun run = run_sclang(*sclang, home, port, "supercollider/commands_test.scd", without_xdg());
    REQUIRE(run.exit_code == 0);
    std::this_thread::sleep_for(200ms);
    dump.stop(SIGTERM, 2s);
    const std::string& seen = dump.output();
    INFO("sclang printed:\n" << run.out << "\noscdump printed:\n" << seen);
    const char* expected[] = {
        "/rain/rate f 10.000000",
        "/rain/wind fff 6.000000 90.000000 0.300000",
        "/rain/dsd sff \"gamma\" 2.000000 3.000000",
        "/drop ffff 3.000000 0.000000 0.200000 0.000000",
        "/drop ffffs 3.000000 0.000000 0.200000 0.000000 \"umbrella\"",
        "/material/liquid s \"milk\"",
        "/material/liquid sfff \"syrup\" 1300.000000 0.070000 5.000000",
        "/material/surface ss \"umbrella\" \"vinyl\"",
        "/scene/load s \"street\"",
        "/scene/save s \"mine\"",
        "/listener ffff 1.000000 0.500000 1.600000 30.000000",
        "/lod fi 50.000000 16",
        "/gain f -6.000000",
        "/loudness f -18.000000",
        "/loudness ",
        "/listener/orientation fff 90.000000 -10.000000 5.000000",
        "/surface/add sssfffff \"roof\" \"plate\" \"tin\" 1.000000 0.600000 0.000000 1.000000 3.000000",
        "/surface/set sssfffff \"roof\" \"plate\" \"glass\" 1.000000 0.600000 0.000000 1.000000 3.000000",
        "/surface/remove s \"roof\"",
        "/sync i 1",
        "/status ",
        "/notify i 1",
        "/version ",
        "/rain/rate ",
        "/quit ",
    };
    check_oscdump_messages(seen, expected);   // and every address is in the server's table
}

TEST_CASE("SuperCollider: a Score written with Score.write renders with ameoto render score, its drops at time x rate + the acoustic delay") {
    const auto sclang = find_program("sclang");
    if (!sclang) return skip_because_absent("sclang", "supercollider-language");
    TempDir home("ameoto-sclang-home");
    const std::string score = temp_path("sclang-score.osc");
    std::filesystem::remove(score);
    const ProgramRun run = run_sclang(*sclang, home, 0, "supercollider/score_test.scd", without_xdg(), {"AMEOTO_TEST_SCORE=" + score});
    INFO("sclang printed:\n" << run.out);
    REQUIRE(run.exit_code == 0);
    auto render = [](const std::string& path, const std::string& wav) {
        const ProgramRun r = run_program(
            {ameoto_bin, "render", "score", path, "-o", wav, "--scene", sharp_onset_scene(), "--rain", "0", "--channels", "1", "--quiet"}, 60s);
        INFO("ameoto printed: " << r.out << r.err);
        REQUIRE(r.exit_code == 0);
        const WavData w = read_wav(wav);
        REQUIRE_MESSAGE(w.ok, w.error);
        return w;
    };
    // The acoustic delay (drop to the listener's ear, and the impact's rise to the threshold): one drop
    // at time 0 of a text score, the same drop.
    const std::string zero = temp_path("sclang-zero.txt");
    std::ofstream(zero) << "0 /drop 3 0 0.2 0\n0.3 /c_set\n";
    const std::vector<long long> at_zero = drop_onsets(render(zero, temp_path("sclang-zero.wav")), 0.02f, 2000);
    REQUIRE(at_zero.size() == 1);
    const WavData w = render(score, temp_path("sclang-score.wav"));
    CHECK(w.frames == 96000);   // the /c_set end marker at 2 s
    const std::vector<long long> onsets = drop_onsets(w, 0.02f, 2000);
    REQUIRE(onsets.size() == 3);
    // Score.write's timetags: 0.5, 0.75, 1.25 s as 32.32 fixed point, exact in binary; at 48 kHz the
    // drops are due at 24000, 36000, 60000; each lands within 1 sample of that plus the delay.
    const long long delay = at_zero[0];
    INFO("delay " << delay << " samples; onsets " << onsets[0] << " " << onsets[1] << " " << onsets[2]);
    CHECK(std::llabs(onsets[0] - 24000 - delay) <= 1);
    CHECK(std::llabs(onsets[1] - 36000 - delay) <= 1);
    CHECK(std::llabs(onsets[2] - 60000 - delay) <= 1);
}
