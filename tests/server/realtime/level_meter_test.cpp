// SPDX-License-Identifier: GPL-3.0-or-later
// The level meter behind /meter: windows of exactly 100 ms across any block size, peak and RMS as
// defined, the dBFS conversion, a full queue that drops readings instead of blocking, and no
// allocation, lock or system call on the audio side.
#include "server/realtime/level_meter.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/relative_approx.hpp"

using ameoto::LevelMeter;
using ameoto::MeterWindow;

namespace {

// Feeds `total` frames of a known two-channel signal in blocks of `block`: channel 0 a full-scale sine
// at 1 kHz (peak 1 within a cycle, RMS 1/sqrt 2 over whole cycles), channel 1 a constant -0.25.
std::vector<MeterWindow> run(LevelMeter& meter, int block, int total, double rate) {
    std::vector<float> left(static_cast<std::size_t>(block)), right(static_cast<std::size_t>(block));
    float* outputs[2] = {left.data(), right.data()};
    std::vector<MeterWindow> windows;
    std::uint64_t frame = 0;
    for (int done = 0; done < total; done += block) {
        for (int k = 0; k < block; ++k) {
            left[static_cast<std::size_t>(k)] = static_cast<float>(std::sin(2.0 * M_PI * 1000.0 * static_cast<double>(frame + k) / rate));
            right[static_cast<std::size_t>(k)] = -0.25f;
        }
        frame += static_cast<std::uint64_t>(block);
        meter.measure(block, outputs, frame);
        MeterWindow w;
        while (meter.take(w)) windows.push_back(w);
    }
    return windows;
}

}  // namespace

TEST_CASE("windows are 100 ms of audio whatever the block size, with the frame at their end") {
    for (const int block : {64, 256, 1000, 4096}) {
        INFO("block " << block);
        LevelMeter meter(48000.0, 2);
        CHECK(meter.window_frames() == 4800);
        const auto windows = run(meter, block, 48000 + 4096, 48000.0);
        REQUIRE(windows.size() >= 10);
        for (std::size_t k = 0; k < 10; ++k) {
            CHECK(windows[k].frame == 4800 * (k + 1));
            CHECK(windows[k].channels == 2);
            // 4800 samples hold exactly 100 cycles of 1 kHz: RMS 1/sqrt(2); the sine reaches within
            // sin(pi/48) of its crest at 48 samples a cycle. Float sums over 4800 samples: 1e-6.
            CHECK(windows[k].peak[0] == doctest::Approx(1.0).epsilon(1e-6));
            CHECK(windows[k].rms[0] == ameoto::test::relative(1.0 / std::sqrt(2.0)).epsilon(1e-6));
            CHECK(windows[k].peak[1] == 0.25f);
            CHECK(windows[k].rms[1] == ameoto::test::relative(0.25).epsilon(1e-6));
        }
    }
}

TEST_CASE("dBFS: full scale is 0, half is -6.02, silence is -120") {
    CHECK(ameoto::to_dbfs(1.0f) == doctest::Approx(0.0));
    CHECK(ameoto::to_dbfs(0.5f) == doctest::Approx(-6.0206).epsilon(1e-4));
    CHECK(ameoto::to_dbfs(0.0f) == -120.0f);
    CHECK(ameoto::to_dbfs(1e-7f) == -120.0f);
}

TEST_CASE("a control thread that never reads loses readings, not audio; the audio side never allocates") {
    LevelMeter meter(8000.0, 1);   // 800-frame windows
    std::vector<float> block(800, 0.5f);
    float* outputs[1] = {block.data()};
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int k = 0; k < 100; ++k) meter.measure(800, outputs, static_cast<std::uint64_t>(800 * (k + 1)));
    }
    CHECK(audit.violations() == 0);
    MeterWindow w;
    int kept = 0;
    std::uint64_t last = 0;
    while (meter.take(w)) {
        ++kept;
        last = w.frame;
    }
    CHECK(kept == 32);            // the queue's capacity: about 3 s of readings
    CHECK(last == 800u * 32u);    // the oldest are kept; the rest were dropped on the audio side
}
