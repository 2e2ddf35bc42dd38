// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/wav_file.hpp"

#include <sndfile.h>

#include <algorithm>
#include <cmath>

namespace ameoto::test {

WavData read_wav(const std::string& path) {
    WavData w;
    SF_INFO info{};
    SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
    if (!f) {
        w.error = sf_strerror(nullptr);
        return w;
    }
    w.frames = info.frames;
    w.channels = info.channels;
    w.sample_rate = info.samplerate;
    w.is_float = (info.format & SF_FORMAT_SUBMASK) == SF_FORMAT_FLOAT;
    w.samples.resize(static_cast<std::size_t>(info.frames * info.channels));
    const sf_count_t got = sf_readf_float(f, w.samples.data(), info.frames);
    sf_close(f);
    w.ok = got == info.frames;
    if (!w.ok) w.error = "short read";
    return w;
}

std::vector<float> WavData::channel(int c) const {
    std::vector<float> out(static_cast<std::size_t>(frames));
    for (long long n = 0; n < frames; ++n) out[static_cast<std::size_t>(n)] = samples[static_cast<std::size_t>(n * channels + c)];
    return out;
}

long long WavData::first_nonzero_frame(float threshold) const {
    for (long long n = 0; n < frames; ++n)
        for (int c = 0; c < channels; ++c)
            if (std::fabs(samples[static_cast<std::size_t>(n * channels + c)]) > threshold) return n;
    return -1;
}

float WavData::peak() const {
    float p = 0.0f;
    for (float v : samples) p = std::max(p, std::fabs(v));
    return p;
}

}  // namespace ameoto::test
