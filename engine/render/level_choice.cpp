// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/level_choice.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/render/loudness.hpp"
#include "engine/render/output_stage.hpp"

namespace ameoto {

namespace {

// The integrated loudness of the physical samples raised by gain_db and passed through the stream's
// limiter (output_stage.hpp, its defaults: -1 dBTP, 2 ms look-ahead, 100 ms release), with the frames the
// look-ahead still holds at the end flushed by silence.
double limited_lufs(const std::vector<float>& interleaved, int channels, double sample_rate, double gain_db) {
    OutputStageConfig o;
    o.channels = channels;
    o.sample_rate = sample_rate;
    o.limiter = true;
    OutputStage stage(o);
    const auto width = static_cast<std::size_t>(channels);
    const std::size_t frames = interleaved.size() / width;
    const auto tail = static_cast<std::size_t>(stage.latency_frames());
    std::vector<float> out((frames + tail) * width, 0.0f);
    const auto g = static_cast<float>(std::pow(10.0, gain_db / 20.0));
    for (std::size_t f = 0; f < frames + tail; ++f) {
        float* frame = out.data() + f * width;
        if (f < frames)
            for (std::size_t c = 0; c < width; ++c) frame[c] = g * interleaved[f * width + c];
        stage.process_frame(frame);
    }
    return integrated_lufs_any_level(out, channels, sample_rate);
}

// The level gain that plays the measured samples at the target through the limiter. Without it the gain is
// target - measured; with it a peaky programme (peak-to-loudness ratio above the target's headroom: 22 dB
// from -23 LUFS to -1 dBTP) would lose to the limiter what it holds back of its peaks (the umbrella in
// air: 2.2 LU). The loudness through the limiter rises with the gain at a slope of 1 or less, so the
// secant from the unlimited gain finds it in a few passes over the recorded samples (no new render). The
// limiter's share is capped at max_limiter_share_db: past that the programme plays below its target
// rather than be flattened (reported in limiter_db and played_lufs).
void through_limiter(LevelChoice& choice, const std::vector<float>& interleaved, int channels, double sample_rate,
                     double target_lufs) {
    const double unlimited = choice.gain_db;
    double g0 = unlimited, l0 = limited_lufs(interleaved, channels, sample_rate, g0);
    double best = g0, best_lufs = l0;
    double g1 = std::clamp(g0 + (target_lufs - l0), unlimited, unlimited + max_limiter_share_db);
    for (int pass = 0; pass < 8 && std::fabs(target_lufs - best_lufs) > 0.02 && g1 != g0; ++pass) {
        const double l1 = limited_lufs(interleaved, channels, sample_rate, g1);
        if (!std::isfinite(l1)) break;
        if (std::fabs(target_lufs - l1) < std::fabs(target_lufs - best_lufs)) {
            best = g1;
            best_lufs = l1;
        }
        const double slope = (l1 - l0) / (g1 - g0);
        double next = slope > 0.05 ? g1 + (target_lufs - l1) / slope : g1 + (target_lufs - l1);
        next = std::clamp(next, unlimited, unlimited + max_limiter_share_db);
        g0 = g1;
        l0 = l1;
        g1 = next;
    }
    choice.gain_db = std::clamp(best, min_level_gain_db, max_level_gain_db);
    choice.limiter_db = choice.gain_db - unlimited;
    choice.played_lufs = best_lufs;
}

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
    if (!std::isfinite(choice.measured_lufs)) return choice;
    auto recording = std::make_shared<LevelRecording>();
    recording->interleaved = std::move(interleaved);
    recording->channels = channels;
    recording->sample_rate = c.sample_rate;
    recording->limiter = config.limiter;
    choice.recording = std::move(recording);
    return retarget_level(choice, target_lufs);
}

}  // namespace

LevelChoice retarget_level(const LevelChoice& measured, double target_lufs) {
    LevelChoice choice = measured;
    choice.limiter_db = 0.0;
    if (!std::isfinite(choice.measured_lufs)) {
        choice.gain_db = 0.0;
        return choice;
    }
    choice.gain_db = std::clamp(target_lufs - choice.measured_lufs, min_level_gain_db, max_level_gain_db);
    choice.played_lufs = choice.measured_lufs + choice.gain_db;
    const LevelRecording* r = choice.recording.get();
    if (r != nullptr && r->limiter) through_limiter(choice, r->interleaved, r->channels, r->sample_rate, target_lufs);
    return choice;
}

LevelChoice choose_level(const RendererConfig& config, double target_lufs, double seconds) {
    return choose(config, nullptr, target_lufs, seconds);
}

LevelChoice choose_level(const RendererConfig& config, const UmbrellaParts& parts, double target_lufs, double seconds) {
    return choose(config, &parts, target_lufs, seconds);
}

}  // namespace ameoto
