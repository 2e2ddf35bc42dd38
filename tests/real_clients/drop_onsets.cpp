// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/real_clients/drop_onsets.hpp"

#include <algorithm>
#include <cmath>

namespace ameoto::test {

std::vector<long long> drop_onsets(const WavData& wav, float threshold, long long gap) {
    std::vector<long long> onsets;
    long long last_loud = -gap - 1;
    for (long long frame = 0; frame < wav.frames; ++frame) {
        float peak = 0.0f;
        for (int c = 0; c < wav.channels; ++c)
            peak = std::max(peak, std::fabs(wav.samples[static_cast<std::size_t>(frame * wav.channels + c)]));
        if (peak <= threshold) continue;
        if (frame - last_loud > gap) onsets.push_back(frame);
        last_loud = frame;
    }
    return onsets;
}

}  // namespace ameoto::test
