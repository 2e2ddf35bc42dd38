// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod on a real JACK server (jackd2, dummy driver, no real-time): recorded with jack-record
// from jack-tools, compared with the null backend, and put through a server crash and return.

#include <doctest/doctest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "tests/support/child_process.hpp"
#include "tests/support/jack_server.hpp"
#include "tests/support/timing_scale.hpp"
#include "tests/support/audio_clock.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/rt_report.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::test::ChildProcess;
using ameoto::test::JackServer;
using ameoto::test::OscTestClient;

namespace {

using ameoto::test::ameotod;

// ameotod ARGS --backend jack --port 0 on that server: listening within 15 s, then running within 10 s.
ameoto::test::DaemonProcess jack_daemon(const JackServer& jack, std::vector<std::string> args, const std::vector<std::string>& env = {}) {
    args.insert(args.end(), {"--backend", "jack"});
    ameoto::test::DaemonOptions options;
    options.listen_timeout = 15s;
    options.running_timeout = 10s;
    return ameoto::test::DaemonProcess(std::move(args), jack.env(env), options);
}

ameoto::test::WavData record(const JackServer& jack, const std::string& client, double seconds, const std::string& name) {
    const std::string path = ameoto::test::temp_path(name);
    ChildProcess rec({"/usr/bin/jack-record", "-b", "262144", "-n", "2", "-p", client + ":out_%d", "-t", std::to_string(seconds), path}, jack.env());
    // The dummy driver's cycle waits for every client, so a slow ameotod (the sanitizers: several times
    // slower) stretches the recording's wall time: the bound is scaled like any wait for a program.
    REQUIRE_MESSAGE(rec.wait(ameoto::test::scaled(std::chrono::milliseconds(static_cast<int>(seconds * 1000) + 15000))) == 0, rec.output());
    return ameoto::test::read_wav(path);
}

}  // namespace

TEST_CASE("JACK: rain plays through JACK, sample-identical to the null backend, with no real-time violations") {
    JackServer jack;
    const std::string report = ameoto::test::temp_path("jack-rt.txt");
    ameoto::test::WavData recorded;
    std::int64_t xruns = 0;
    {
        // --fixed-detail: a live stream otherwise sheds detail when the measured load passes the budget,
        // and then (rightly) differs from the offline render.
        auto d = jack_daemon(jack, {"--jack-name", "ameoto_t1", "--seed", "11", "--autoconnect", "--fixed-detail"},
                         {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report});
        // --autoconnect: out_1 and out_2 feed the (dummy) system playback ports.
        const auto connections = ameoto::test::run_program({"jack_lsp", "-c", "ameoto_t1:out_1"}, 10s, jack.env());
        CHECK(connections.out.find("system:playback_1") != std::string::npos);
        recorded = record(jack, "ameoto_t1", 2.0, "jack.wav");
        OscTestClient client(d.port());
        const auto s = ameoto::test::status_reply(client);
        CHECK(s.args[12].text == "jack");
        CHECK(s.args[8].number == 48000.0);
        CHECK(s.args[9].integer == 256);
        CHECK(s.args[2].number > 100.0);   // drops per second at the default 2 mm/h
        xruns = s.args[6].integer;
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    REQUIRE_MESSAGE(recorded.ok, recorded.error);
    REQUIRE(recorded.frames == 96000);
    REQUIRE(recorded.is_float);

    // The audio thread under JACK: the probe was live in every cycle and saw nothing forbidden.
    const auto rt = ameoto::test::read_rt_report(report);
    INFO(rt.text);
    CHECK(rt.no_violations());
    CHECK(rt.probed());

    // The same seed, offline on the null backend with another block size: the JACK recording must
    // appear in it sample for sample (it started a little after the daemon, at an unknown offset).
    const std::string null_path = ameoto::test::temp_path("null-same-seed.wav");
    ChildProcess offline({ameotod, "--backend", "null", "--offline", "--duration", "15", "--seed", "11", "--block", "1000",
                          "--output", null_path, "--port", "0", "--level", "physical"});   // as the harness starts the JACK one
    REQUIRE(offline.wait(120s) == 0);
    const auto rendered = ameoto::test::read_wav(null_path);
    REQUIRE(rendered.ok);
    // jack-record's first one or two periods can be silence (it connects its ports while running), so
    // the match starts at the first recorded frame that is not zero; everything from there on must be
    // identical, and those leading zeros are at most a few periods.
    const long long first = recorded.first_nonzero_frame();
    REQUIRE(first >= 0);
    // With xruns, cycles lost while jack-record connected lengthen that silence (7 periods with 84 xruns).
    if (xruns == 0) CHECK(first <= 4 * 256);
    // Find where a recorded period starts in the render, then how far the two agree sample for sample.
    // Normally the first non-zero period matches; after an xrun inside it, a later period does.
    auto frame_equal = [&](long long rec, long long ren) {
        return recorded.samples[static_cast<std::size_t>(2 * rec)] == rendered.samples[static_cast<std::size_t>(2 * ren)] &&
               recorded.samples[static_cast<std::size_t>(2 * rec + 1)] == rendered.samples[static_cast<std::size_t>(2 * ren + 1)];
    };
    // jack-record connects its two ports one after the other while running, so its first non-zero
    // period may hold one channel only: the match may start up to 4 periods after `first`.
    long long match = -1, agreed = 0, start = first;
    for (; start + 256 <= recorded.frames && match < 0 && (xruns > 0 || start <= first + 4 * 256); start += 256) {
        for (long long k = 0; k + 256 <= rendered.frames && match < 0; ++k) {
            long long n = 0;
            while (n < 256 && frame_equal(start + n, k + n)) ++n;
            if (n < 256) continue;
            match = k;
            while (start + agreed < recorded.frames && k + agreed < rendered.frames && frame_equal(start + agreed, k + agreed)) ++agreed;
        }
    }
    if (match >= 0) start -= 256;   // the loop stepped past the period that matched
    const long long wanted = recorded.frames - start;
    INFO("JACK recording from frame " << start << " (first non-zero " << first << ") found in the null render at frame " << match
         << "; identical for " << agreed << " of " << wanted
         << " frames; xruns during the run: " << xruns);
    REQUIRE(match >= 0);
    if (xruns == 0) {
        CHECK(agreed == wanted);
    } else {
        // A JACK xrun skips a cycle: the recording then holds a gap the render does not. Up to the
        // first xrun the two must still be identical; on an idle machine (CI) there are none.
        MESSAGE("JACK reported " << xruns << " xruns; identical for the first " << agreed << " frames");
        CHECK(agreed >= 256);
    }
}

TEST_CASE("JACK: a /drop over OSC is heard, with silence before it") {
    JackServer jack;
    auto d = jack_daemon(jack, {"--jack-name", "ameoto_t2", "--rain", "0"});
    const std::string path = ameoto::test::temp_path("jack-drop.wav");
    ChildProcess rec({"/usr/bin/jack-record", "-b", "262144", "-n", "2", "-p", "ameoto_t2:out_%d", "-t", "2", path}, jack.env());
    std::this_thread::sleep_for(700ms);
    OscTestClient client(d.port());
    client.send("/drop", {OscArgument::from_float(3.0f), OscArgument::from_float(0.0f), OscArgument::from_float(0.2f),
                          OscArgument::from_float(0.0f)});
    REQUIRE(rec.wait(ameoto::test::scaled(20s)) == 0);
    const auto w = ameoto::test::read_wav(path);
    REQUIRE(w.ok);
    const long long onset = w.first_nonzero_frame();
    CHECK(onset > 4800);              // silence for the first 100 ms of the recording at least
    CHECK(onset < w.frames - 4800);   // and the drop well inside it
    float peak = 0.0f;
    for (float s : w.samples) peak = std::max(peak, std::fabs(s));
    CHECK(peak > 1e-3f);
}

TEST_CASE("JACK: the server dies and returns; ameotod keeps answering OSC and plays again") {
    JackServer jack;
    auto d = jack_daemon(jack, {"--jack-name", "ameoto_t3"});
    OscTestClient client(d.port());
    const auto before = ameoto::test::audio_seconds(client);
    CHECK(before > 0);

    jack.stop();
    REQUIRE_MESSAGE(d.process().wait_for_line("went away", 10s), d.process().output());
    std::this_thread::sleep_for(300ms);   // a callback running when jackd stopped may finish its block
    const auto frozen_a = ameoto::test::audio_seconds(client);   // OSC still answers while JACK is gone
    std::this_thread::sleep_for(300ms);
    const auto frozen_b = ameoto::test::audio_seconds(client);
    CHECK(frozen_a == frozen_b);                               // and no audio runs without a server

    const auto restart = std::chrono::steady_clock::now();
    jack.start();
    REQUIRE_MESSAGE(d.process().wait_for_line("JACK server is back", 10s), d.process().output());
    const double back_after = std::chrono::duration<double>(std::chrono::steady_clock::now() - restart).count();
    MESSAGE("playing again " << back_after << " s after jackd was started again (includes jack_wait)");
    std::this_thread::sleep_for(300ms);
    CHECK(ameoto::test::audio_seconds(client) > frozen_b);         // the sample clock runs on
    CHECK(d.process().running());
}
