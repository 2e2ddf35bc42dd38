// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Reads a whole WAV (or any libsndfile format) for a test.
//
// Interface:
//   WavData w = read_wav(path);     // w.ok false (and w.error) when unreadable
//   w.frames, w.channels, w.sample_rate, w.samples (interleaved float), w.channel(c)

#include <string>
#include <vector>

namespace ameoto::test {

struct WavData {
    bool ok = false;
    std::string error;
    long long frames = 0;
    int channels = 0;
    int sample_rate = 0;
    bool is_float = false;
    std::vector<float> samples;
    std::vector<float> channel(int c) const;
    long long first_nonzero_frame(float threshold = 0.0f) const;   // -1 when silent
    float peak() const;                                             // the largest |sample|, 0 when silent
};

WavData read_wav(const std::string& path);

}  // namespace ameoto::test
