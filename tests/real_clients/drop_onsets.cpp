// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/real_clients/drop_onsets.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "tests/support/temp_dir.hpp"

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

std::string sharp_onset_scene() {
    const std::string path = temp_path("umbrella-in-vacuum.scene");
    std::ofstream file(path);
    // builtin_scenes.cpp's umbrella: 1 m of nylon over the head (shaft top 1.9 m, ears 1.6 m), 2 mm/h.
    file << "ameoto-scene 1\n"
            "name umbrella-in-vacuum\n"
            "rain rate=2\n"
            "listener x=0 y=0 z=1.6 facing=0\n"
            "surface umbrella kind=umbrella material=nylon size=1 z=1.9 air=off\n";
    return path;
}

}  // namespace ameoto::test
