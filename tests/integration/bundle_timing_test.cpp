// SPDX-License-Identifier: GPL-3.0-or-later
// Bundles are scheduled to the sample: drops in nested bundles at known times land in the null
// backend's output exactly that many samples apart (+/- 1, the rounding of each timetag to a sample;
// read here as -1 to +2, below).
//
// How the landing sample is seen without guessing at onsets: with --rain 0 and --fixed-detail the stream
// depends only on the seed and the commands (daemon_test: "offline renders are exact ..."), and nothing
// sounds before the first drop, so two runs that share their first drop are identical sample for sample,
// once aligned on that drop's onset, until the next drop that differs between them. The first differing
// sample is where that drop landed, relative to the first, or one sample after it: a drop's first sounding
// sample is tiny (its sound grows from the first contact: -7.8e-11 for A alone), and added to the first
// drop's ringing in 32-bit floats (4.2e-4 where B lands) it can change nothing. Every run here read B 4801
// and C 12001 samples after A (2026-12-07), so the window is the timetag's rounding, +/- 1, and that one
// sample more above: 4799-4802 and 11999-12002. A window on the drops' own onsets instead (where the runs
// part by a thousandth or a millionth of the first drop's peak, against where that drop passes the same
// level) read 4795 and 4798: the later drop strikes a canopy already moving, so its sound is not the
// first's shifted, and a level's crossing moves with it.

#include <doctest/doctest.h>
#include <signal.h>

#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "tests/support/audio_clock.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::protocol::Timetag;
using Daemon = ameoto::test::DaemonProcess;

namespace {

constexpr double rate = 48000.0;

double wall() {
    timespec t{};
    clock_gettime(CLOCK_REALTIME, &t);
    return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
}

std::vector<unsigned char> drop() {
    return ameoto::protocol::encode_message(
        "/drop", {OscArgument::from_float(3.0f), OscArgument::from_float(0.0f), OscArgument::from_float(0.15f), OscArgument::from_float(0.05f)});
}

// Plays one packet `build(now)` on a fresh, dry, fixed-detail daemon and returns its output from the
// first sounding sample on.
std::vector<float> play(const std::string& name, const std::function<std::vector<unsigned char>(double)>& build) {
    const std::string wav = ameoto::test::temp_path(name);
    {
        ameoto::test::DaemonOptions slow_start;   // building the scene takes seconds on a loaded machine
        slow_start.listen_timeout = 30s;
        Daemon d({"--backend", "null", "--output", wav, "--realtime", "--rain", "0", "--fixed-detail", "--channels", "1"}, {}, slow_start);
        ameoto::test::OscTestClient c(d.port());
        std::this_thread::sleep_for(200ms);   // the audio clock is published
        c.send_raw(build(wall()));
        // 1.2 s of audio after sending (the last drop is due 0.55 s after it), counted in the stream's own
        // seconds: under the sanitizers the engine runs slower than real time, and a fixed wall-clock wait
        // stopped the daemon before the last drop was rendered (its frame is on the backend's deadline grid).
        ameoto::test::wait_for_audio(c, 1.2);
        REQUIRE(c.request("/sync", {OscArgument::from_int(1)}, "/synced", 2s));
        REQUIRE(d.process().stop(SIGTERM, 5s) == 0);
    }
    const auto w = ameoto::test::read_wav(wav);
    REQUIRE(w.ok);
    const long long onset = w.first_nonzero_frame();
    REQUIRE(onset >= 0);
    return std::vector<float>(w.samples.begin() + onset, w.samples.end());
}

long long first_difference(const std::vector<float>& a, const std::vector<float>& b) {
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t k = 0; k < n; ++k)
        if (a[k] != b[k]) return static_cast<long long>(k);
    return -1;
}

}  // namespace

TEST_CASE("drops in nested bundles land at their timetags to the sample, -1 to +2 as seen") {
    using ameoto::protocol::encode_bundle;
    const double lead = 0.3;                      // s: time for the packet to arrive before the first drop
    const double b_after = 0.1, c_after = 0.25;   // s after the first drop: 4800 and 12000 samples
    // A alone; A with B one bundle deep; A with B and C two bundles deep (C inside B's bundle).
    const auto a_only = play("timing-a.wav", [&](double now) { return encode_bundle(Timetag::from_unix_seconds(now + lead), {drop()}); });
    auto play_a_b = [&] {
        return play("timing-ab.wav", [&](double now) {
            const double t = now + lead;
            return encode_bundle(Timetag::from_unix_seconds(t), {drop(), encode_bundle(Timetag::from_unix_seconds(t + b_after), {drop()})});
        });
    };
    auto play_a_b_c = [&] {
        return play("timing-abc.wav", [&](double now) {
            const double t = now + lead;
            const auto inner = encode_bundle(Timetag::from_unix_seconds(t + c_after), {drop()});
            return encode_bundle(Timetag::from_unix_seconds(t), {drop(), encode_bundle(Timetag::from_unix_seconds(t + b_after), {drop(), inner})});
        });
    };
    auto b_within_one = [&](long long b) {   // the rounding, and the first difference's lag (above)
        CHECK(b >= static_cast<long long>(b_after * rate) - 1);
        CHECK(b <= static_cast<long long>(b_after * rate) + 2);
    };
    std::vector<float> a_b = play_a_b();
    long long b_at = first_difference(a_only, a_b);
    b_within_one(b_at);
    // Each run reads its own clock and rounds each timetag to a frame on its own (in seconds since 1970
    // as a double: steps of 2.4e-7 s, 0.01 sample), so B lands 4800 in some runs and 4801 in others (both
    // within +/- 1). C is found as the first difference from the A+B run, which needs B on the same
    // sample in both: either run is played again (each checked to +/- 1) until a pair agrees. Three
    // A+B+C runs against one A+B missed once in CI (4801 against 4800 each time); with up to 8 more plays
    // and either side free to move, a miss needs every pair to disagree.
    std::vector<float> a_b_c = play_a_b_c();
    long long b_again = first_difference(a_only, a_b_c);
    b_within_one(b_again);
    for (int attempt = 0; attempt < 8 && b_again != b_at; ++attempt) {
        if (attempt % 2 == 0) {
            a_b = play_a_b();
            b_at = first_difference(a_only, a_b);
            b_within_one(b_at);
        } else {
            a_b_c = play_a_b_c();
            b_again = first_difference(a_only, a_b_c);
            b_within_one(b_again);
        }
    }
    const long long c_at = first_difference(a_b, a_b_c);
    INFO("B at " << b_at << " (again " << b_again << "), C at " << c_at << " samples after A");
    REQUIRE(b_again == b_at);
    CHECK(c_at >= static_cast<long long>(c_after * rate) - 1);
    CHECK(c_at <= static_cast<long long>(c_after * rate) + 2);
}
