// SPDX-License-Identifier: GPL-3.0-or-later
// The shipped Python example clients/python/ameoto_example.py, run by Debian's /usr/bin/python3 with
// python3-liblo against the real ameotod: its /status.reply, the rate it sets, and its timed bundles
// landing in the null backend's WAV at their samples.

#include <doctest/doctest.h>
#include <signal.h>
#include <time.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/real_clients/drop_onsets.hpp"
#include "tests/real_clients/real_programs.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test;

namespace {

// Debian's interpreter, where python3-liblo installs; a python3 earlier in PATH (pyenv) lacks it.
const std::string python = "/usr/bin/python3";

bool pyliblo_present() {
    return run_program({python, "-c", "import liblo"}, 10s).exit_code == 0;
}

ProgramRun run_example(int port, const std::vector<std::string>& options) {
    std::vector<std::string> argv = {python, client_path("python/ameoto_example.py"), "--port", std::to_string(port)};
    argv.insert(argv.end(), options.begin(), options.end());
    return run_program(argv, 15s);
}

// "bundle N: /drop D mm at NTP SECONDS" lines, as Unix seconds.
std::vector<double> bundle_times(const std::string& output) {
    constexpr double ntp_to_unix = 2208988800.0;   // seconds from 1900 to 1970
    std::vector<double> times;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        const auto at = line.find(" at NTP ");
        if (line.rfind("bundle ", 0) == 0 && at != std::string::npos)
            times.push_back(std::strtod(line.c_str() + at + 8, nullptr) - ntp_to_unix);
    }
    return times;
}

double wall_seconds() {
    timespec t{};
    clock_gettime(CLOCK_REALTIME, &t);
    return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
}

}  // namespace

TEST_CASE("Python: the example sets the rate, sends drops and prints /status.reply by name") {
    if (!pyliblo_present()) return skip_because_absent("/usr/bin/python3 with liblo", "python3-liblo");
    DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0"}, {}, DaemonOptions::patient());
    const ProgramRun run = run_example(d.port(), {"--rate", "10", "--drops", "2", "--bundle-in", "0.1", "--bundle-drops", "1"});
    INFO("the example printed:\n" << run.out);
    REQUIRE(run.exit_code == 0);
    const auto status = name_value_lines(run.out, "");
    CHECK(status.at("backend") == "null");
    CHECK(status.at("sample_rate_hz") == "48000.0");
    CHECK(status.at("block_size_frames") == "256");
    CHECK(status.at("late_bundles") == "0");
    CHECK(std::stod(status.at("seconds_rendered")) > 0.0);
    OscTestClient client(d.port());
    CHECK(settled_rain_rate(client) == doctest::Approx(10.0).epsilon(1e-6));

    // A refused rate: the example reports the server's reason and exits 1; the rate stays.
    const ProgramRun refused = run_example(d.port(), {"--rate", "900", "--drops", "0", "--bundle-drops", "0"});
    CHECK(refused.exit_code == 1);
    CHECK(refused.out.find("ameotod refused /rain/rate: argument 1 rate (mm/h): 900 is outside 0..500") != std::string::npos);
    CHECK(settled_rain_rate(client) == doctest::Approx(10.0).epsilon(1e-6));
}

TEST_CASE("Python: timed bundles of drops sound at their timetags' samples, 0.25 s apart to +/- 1 sample") {
    if (!pyliblo_present()) return skip_because_absent("/usr/bin/python3 with liblo", "python3-liblo");
    const std::string wav = temp_path("python-bundles.wav");
    ProgramRun run;
    long long frame_then = 0;
    double wall_then = 0.0;
    {
        DaemonProcess d({"--backend", "null", "--output", wav, "--realtime", "--rain", "0", "--scene", sharp_onset_scene()}, {}, DaemonOptions::patient());
        OscTestClient client(d.port());
        // A (wall clock, frame) pair: the reply's frame was current within a block of wall_then.
        wall_then = wall_seconds();
        const auto status = client.request("/status", {}, "/status.reply", 2s);
        REQUIRE(status);
        frame_then = std::llround(status->args[10].number * 48000.0);   // field 11: seconds of audio
        run = run_example(d.port(), {"--rate", "0", "--drops", "0", "--bundle-in", "0.5", "--bundle-spacing", "0.25",
                                     "--bundle-drops", "3"});
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    INFO("the example printed:\n" << run.out);
    REQUIRE(run.exit_code == 0);
    const WavData w = read_wav(wav);
    REQUIRE_MESSAGE(w.ok, w.error);
    if (stop_here_if_sanitized("the null backend's real-time schedule: the audio runs slower than real time, so bundles come late"))
        return;
    CHECK(name_value_lines(run.out, "").at("late_bundles") == "0");
    const std::vector<double> times = bundle_times(run.out);
    REQUIRE(times.size() == 3);
    REQUIRE(w.sample_rate == 48000);
    const std::vector<long long> onsets = drop_onsets(w, 0.02f, 2000);
    REQUIRE(onsets.size() == 3);
    // Relative: each timetag becomes a frame by one rounding (AudioBridge::frame_for), so identical
    // drops 0.25 s apart start 12000 frames apart, +/- 1 for the two roundings.
    for (std::size_t i = 1; i < onsets.size(); ++i) {
        const long long expected = std::llround((times[i] - times[i - 1]) * 48000.0);
        CAPTURE(i);
        CHECK(std::llabs(onsets[i] - onsets[i - 1] - expected) <= 1);
    }
    // Absolute: the first drop at its timetag, plus the sound's travel to the listener (42..71
    // samples for the umbrella, docs/PROTOCOL.md /drop), against the (wall, frame) pair read before:
    // within two blocks and 30 ms of scheduling slack on a shared machine, as in daemon_test.cpp.
    const double expected_first = static_cast<double>(frame_then) + (times[0] - wall_then) * 48000.0;
    INFO("first onset " << onsets[0] << ", timetag's frame about " << expected_first);
    CHECK(static_cast<double>(onsets[0]) >= expected_first + 42 - 2 * 256 - 1440);
    CHECK(static_cast<double>(onsets[0]) <= expected_first + 71 + 2 * 256 + 1440);
}
