// SPDX-License-Identifier: GPL-3.0-or-later
// /notify against the real daemon over UDP: periodic /status.reply, /meter levels that match the
// samples written, unsubscribing, the bound on subscribers, and clients that vanish.

#include <doctest/doctest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "engine/render/loudness.hpp"
#include "tests/support/audio_clock.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/timing_scale.hpp"
#include "tests/support/wav_file.hpp"
#include "tests/support/osc_shorthand.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace std::chrono_literals;
using ameoto::protocol::DecodedMessage;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;
// ameotod ARGS --port 0 (DaemonOptions' start-up bound allows for a loaded machine).
using Daemon = ameoto::test::DaemonProcess;

namespace {

// Everything that arrives within `span`.
std::vector<DecodedMessage> collect(OscTestClient& c, std::chrono::milliseconds span) {
    std::vector<DecodedMessage> got;
    const auto end = std::chrono::steady_clock::now() + span;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
        if (left.count() <= 0) break;
        if (auto m = c.receive(left)) got.push_back(std::move(*m));
    }
    return got;
}

long count(const std::vector<DecodedMessage>& ms, const std::string& address) {
    return std::count_if(ms.begin(), ms.end(), [&](const DecodedMessage& m) { return m.address == address; });
}

double dbfs(double linear) { return linear > 1e-6 ? 20.0 * std::log10(linear) : -120.0; }

}  // namespace

TEST_CASE("a subscriber gets /status.reply every second and /meter ten times a second, levels as written") {
    const std::string wav = ameoto::test::temp_path("notify.wav");
    std::vector<DecodedMessage> got;
    double audio_from = 0.0, audio_to = 0.0;   // the audio clock (seconds rendered) around the collection
    {
        // --level auto, as ameotod runs by default: the levels are those of the samples written, whatever the gain.
        Daemon d({"--backend", "null", "--output", wav, "--rain", "40", "--fixed-detail", "--level", "auto"});
        OscTestClient c(d.port());
        // Read before subscribing: a periodic /status.reply could otherwise answer this request, and
        // the real answer would then be counted among the notifications below.
        audio_from = ameoto::test::audio_seconds(c);
        const auto done = c.request("/notify", {i(1)}, "/done", 2s);
        REQUIRE(done);
        CHECK(done->args[0].text == "/notify");
        got = collect(c, 2500ms);
        audio_to = ameoto::test::audio_seconds(c);
        CHECK(c.request("/notify", {}, "/notify.reply", 2s)->args[0].integer == 1);
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    // /status.reply is sent once a second of wall time: 2.5 s hold 2 or 3.
    CHECK(count(got, "/status.reply") >= 2);
    CHECK(count(got, "/status.reply") <= 3);
    // /meter is one reading per 4800 frames (0.1 s) of audio, so the count follows the audio clock, not
    // the wall's: a loaded machine, or the sanitizers, can leave the null backend rendering slower than
    // real time (2.5 s of wall time gave 0.5 s of audio under ASan in CI). The lower bound allows for a
    // busy control thread (readings that wait are merged into the newest), as before in the normal
    // build (10 of about 25); not for a wrong rate (one a block would be 470 a second, one a second 2).
    const double expected = 10.0 * (audio_to - audio_from);
    INFO("audio clock " << audio_from << " s -> " << audio_to << " s: " << expected << " readings expected");
    CHECK(count(got, "/meter") >= 1);
    CHECK(static_cast<double>(count(got, "/meter")) >= 0.4 * expected - 1.0);
    CHECK(static_cast<double>(count(got, "/meter")) <= expected + 2.0);
    for (const auto& m : got)
        if (m.address == "/status.reply") CHECK(m.types == "fffiiiiififfsfif");

    // Each /meter is the peak and RMS of the 100 ms (4800 frames) of the stream that end at its frame:
    // recomputed here from the WAV (32-bit float, the same samples), they agree to 0.01 dB (float
    // rounding of the server's running sums; relative 1e-4 of a level near -40 dB is 0.004 dB).
    const auto w = ameoto::test::read_wav(wav);
    REQUIRE(w.ok);
    REQUIRE(w.channels == 2);
    int checked = 0;
    for (const auto& m : got) {
        if (m.address != "/meter") continue;
        REQUIRE(m.types == "fifffffff");   // time, channels, peak and RMS of 2 channels, momentary, short-term, true peak
        const long long end = std::llround(m.args[0].number * 48000.0);   // seconds at the null backend's 48 kHz
        CHECK(m.args[1].integer == 2);
        if (end > w.frames || end < 4800) continue;
        for (int ch = 0; ch < 2; ++ch) {
            double peak = 0.0, sum = 0.0;
            for (long long k = end - 4800; k < end; ++k) {
                const double x = w.samples[static_cast<std::size_t>(k * 2 + ch)];
                peak = std::max(peak, std::fabs(x));
                sum += x * x;
            }
            INFO("frame " << end << " channel " << ch);
            CHECK(m.args[2 + 2 * ch].number == doctest::Approx(dbfs(peak)).epsilon(1e-4));
            CHECK(m.args[3 + 2 * ch].number == doctest::Approx(dbfs(std::sqrt(sum / 4800))).epsilon(1e-4));
            CHECK(m.args[3 + 2 * ch].number <= m.args[2 + 2 * ch].number);
            CHECK(m.args[2 + 2 * ch].number > -120.0);   // 40 mm/h of rain is not silence
        }
        // The loudness (momentary, 400 ms) of the newest samples when it was sent, recomputed with libebur128
        // from the 400 ms of the WAV that end at the window's frame: the server read a few ms more at most
        // (its 5 ms poll, a block), and rain's momentary loudness moves little in that: 1.5 LU.
        if (end >= 19200) {
            ameoto::LoudnessMeter reference(2, 48000.0, 0);
            reference.add(&w.samples[static_cast<std::size_t>((end - 19200) * 2)], 19200);
            CHECK(std::fabs(m.args[6].number - reference.momentary_lufs()) <= 1.5);
        }
        CHECK(m.args[7].number > -120.0);                                         // short-term: 3 s of heavy rain
        CHECK(m.args[8].number >= std::max(m.args[2].number, m.args[4].number) - 1.0);   // true peak >= the peaks, about
        CHECK(m.args[0].number >= audio_from - 0.2);   // a reading of the audio rendered meanwhile
        CHECK(m.args[0].number <= audio_to + 0.2);
        ++checked;
    }
    CHECK(checked >= count(got, "/meter") - 1);   // only the first reading may start before frame 4800
}

TEST_CASE("/notify 0 stops the notifications; a silent stream meters -120 dBFS") {
    Daemon d({"--backend", "null", "--output", "-", "--rain", "0"});
    OscTestClient c(d.port());
    REQUIRE(c.request("/notify", {i(1)}, "/done", 2s));
    const auto before = collect(c, ameoto::test::scaled(600ms));   // longer under the sanitizers: a slower audio clock
    REQUIRE(count(before, "/meter") >= 1);
    for (const auto& m : before)
        if (m.address == "/meter") {
            CHECK(m.args[2].number == -120.0f);
            CHECK(m.args[3].number == -120.0f);
            CHECK(m.args[6].number == -120.0f);   // momentary, short-term loudness and true peak of silence
            CHECK(m.args[7].number == -120.0f);
            CHECK(m.args[8].number == -120.0f);
        }
    REQUIRE(c.request("/notify", {i(0)}, "/done", 2s));
    collect(c, 100ms);   // what was already on its way
    const auto after = collect(c, 1300ms);
    CHECK(count(after, "/meter") == 0);
    CHECK(count(after, "/status.reply") == 0);
    CHECK(c.request("/notify", {}, "/notify.reply", 2s)->args[0].integer == 0);
    // Leaving twice, or subscribing twice, is harmless and answered the same way.
    CHECK(c.request("/notify", {i(0)}, "/done", 2s));
    CHECK(c.request("/notify", {i(1)}, "/done", 2s));
    CHECK(c.request("/notify", {i(1)}, "/done", 2s));
}

TEST_CASE("at most 16 subscribers: the 17th gets /fail; a vanished subscriber harms no one") {
    Daemon d({"--backend", "null", "--output", "-", "--rain", "5"});
    std::vector<std::unique_ptr<OscTestClient>> clients;
    for (int k = 0; k < 16; ++k) {
        clients.push_back(std::make_unique<OscTestClient>(d.port()));
        REQUIRE(clients.back()->request("/notify", {i(1)}, "/done", 2s));
    }
    OscTestClient late(d.port());
    const auto fail = late.request("/notify", {i(1)}, "/fail", 2s);
    REQUIRE(fail);
    CHECK(fail->args[0].text == "/notify");
    CHECK(fail->args[1].text.find("at most 16") != std::string::npos);
    // Half the subscribers vanish without a word (their ports now refuse): the server keeps sending to
    // them and keeps serving everyone else.
    clients.resize(8);
    std::this_thread::sleep_for(1500ms);
    CHECK(d.process().running());
    CHECK(late.request("/status", {}, "/status.reply", 2s));
    const auto still = collect(*clients.front(), ameoto::test::scaled(500ms));
    CHECK(count(still, "/meter") >= 2);
    // One leaves properly: its place is free.
    REQUIRE(clients.back()->request("/notify", {i(0)}, "/done", 2s));
    CHECK(late.request("/notify", {i(1)}, "/done", 2s));
}
