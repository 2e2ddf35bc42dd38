// SPDX-License-Identifier: GPL-3.0-or-later
// The live binaural stage's limiter acts on the two decoded ears (server/realtime/binaural_stage.hpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "server/realtime/binaural_stage.hpp"

namespace {

// The peak of each ear over `blocks` blocks of a loud bus: W and Y (a source at the left) carrying a
// 1 kHz tone of amplitude 3, well over full scale in the near ear once decoded.
float ears_peak(bool limiter, int blocks, int* latency) {
    auto made = ameoto::BinauralStage::create(ameoto::BinauralDecoder::default_sofa_path, 3, 48000.0, 256, limiter);
    REQUIRE(made.stage);
    ameoto::BinauralStage& stage = *made.stage;
    *latency = stage.latency_frames();
    std::vector<float> left(256), right(256);
    float peak = 0.0f;
    long n = 0;
    for (int b = 0; b < blocks; ++b) {
        float* const* bus = stage.bus();
        for (int i = 0; i < 256; ++i, ++n) {
            const float x = 3.0f * static_cast<float>(std::sin(2.0 * 3.141592653589793 * 1000.0 * static_cast<double>(n) / 48000.0));
            for (int c = 0; c < stage.bus_channels(); ++c) bus[c][i] = 0.0f;
            bus[0][i] = x;
            bus[1][i] = x;   // ACN 1 = Y: towards the left
        }
        stage.decode(256, left.data(), right.data());
        for (int i = 0; i < 256; ++i) peak = std::max({peak, std::fabs(left[static_cast<std::size_t>(i)]), std::fabs(right[static_cast<std::size_t>(i)])});
    }
    return peak;
}

}  // namespace

TEST_CASE("BinauralStage: the limiter holds the decoded ears under the ceiling; off, they pass it") {
    int latency_on = 0, latency_off = 0;
    const float unlimited = ears_peak(false, 40, &latency_off);
    const float limited = ears_peak(true, 40, &latency_on);
    // The ceiling: -1 dBFS (OutputStageConfig's default); the limiter's own guarantee is by construction
    // (engine/render/output_stage.hpp), so no tolerance beyond float rounding of the ceiling itself.
    const float ceiling = static_cast<float>(std::pow(10.0, -1.0 / 20.0));
    CHECK(unlimited > 2.0f * ceiling);
    CHECK(limited <= ceiling);
    CHECK(limited > 0.9f * ceiling);   // limited, not silenced
    CHECK(latency_off == 0);
    CHECK(latency_on == 96 - 1 + ameoto::OutputStage::true_peak_lag);   // 2 ms at 48 kHz, plus the interpolation's wait
}
