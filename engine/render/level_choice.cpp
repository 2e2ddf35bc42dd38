// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/level_choice.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/render/loudness.hpp"

namespace ameoto {

namespace {

LevelChoice choose(const RendererConfig& config, const UmbrellaParts* parts, double target_lufs, double seconds) {
    RendererConfig c = config;
    c.level_gain_db = 0.0;
    c.gain_db = 0.0;
    c.limiter = false;
    c.adaptive_lod = false;   // the same samples on any machine load
    c.rain_rate_mm_per_h = c.scene.rain.rate_mm_per_h;
    c.node = 0;   // the whole scene on every node: each node plays with the same gain, so the nodes sum to it
    // An Ambisonic bus is measured as the stereo stream of the same scene: a loudness summed over SH
    // channels would depend on the order (R 128 weights loudspeaker channels, not SH components), and a
    // scene should play at one gain whatever the format.
    if (c.listener == ListenerStyle::ambix) {
        c.listener = ListenerStyle::panned;
        c.channels = 2;
    }
    LevelChoice choice;
    choice.seconds = seconds;
    if (!(c.rain_rate_mm_per_h > 0.0)) {
        choice.measured_lufs = -HUGE_VAL;
        return choice;
    }
    Renderer renderer(c, parts);
    const int channels = c.channels;
    const long total = std::max(1L, std::lround(seconds * c.sample_rate));
    constexpr int block = 1024;
    std::vector<std::vector<float>> planar(static_cast<std::size_t>(channels), std::vector<float>(block));
    std::vector<float*> out(static_cast<std::size_t>(channels));
    for (int ch = 0; ch < channels; ++ch) out[static_cast<std::size_t>(ch)] = planar[static_cast<std::size_t>(ch)].data();
    std::vector<float> interleaved(static_cast<std::size_t>(total) * static_cast<std::size_t>(channels));
    for (long done = 0; done < total;) {
        const int n = static_cast<int>(std::min<long>(block, total - done));
        renderer.process(n, out.data());
        for (int i = 0; i < n; ++i)
            for (int ch = 0; ch < channels; ++ch)
                interleaved[static_cast<std::size_t>((done + i) * channels + ch)] = planar[static_cast<std::size_t>(ch)][static_cast<std::size_t>(i)];
        done += n;
    }
    choice.measured_lufs = integrated_lufs_any_level(interleaved, channels, c.sample_rate);
    if (std::isfinite(choice.measured_lufs))
        choice.gain_db = std::clamp(target_lufs - choice.measured_lufs, min_level_gain_db, max_level_gain_db);
    return choice;
}

}  // namespace

LevelChoice choose_level(const RendererConfig& config, double target_lufs, double seconds) {
    return choose(config, nullptr, target_lufs, seconds);
}

LevelChoice choose_level(const RendererConfig& config, const UmbrellaParts& parts, double target_lufs, double seconds) {
    return choose(config, &parts, target_lufs, seconds);
}

}  // namespace ameoto
