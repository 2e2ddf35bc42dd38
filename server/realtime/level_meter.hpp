// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Level meters for /meter: the audio thread measures each channel's peak and RMS over fixed windows
// of samples and hands each finished window to the control thread through a fixed-size lock-free
// queue; the control thread turns them into dBFS.
//
// Interface:
//   LevelMeter meter(sample_rate, channels);              // control thread, allocates the queue once
//   audio thread:   meter.measure(frames, outputs, end_frame);   // never allocates, locks or blocks
//   control thread: MeterWindow w; while (meter.take(w)) ...     // oldest first
//   to_dbfs(w.peak[c]), to_dbfs(w.rms[c])                        // -120 dBFS for silence
//
// A window is window_seconds of audio (100 ms: ten meter readings a second, as a VU-style display
// wants); its frame is the stream frame just after its last sample. When the control thread falls
// behind, the newest windows are dropped (the queue holds about 3 s), never the audio.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "server/realtime/spsc_queue.hpp"

namespace ameoto {

inline constexpr int max_meter_channels = 16;   // --channels allows at most 16

struct MeterWindow {
    std::uint64_t frame = 0;
    int channels = 0;
    std::array<float, max_meter_channels> peak{};   // linear full scale, |x| max
    std::array<float, max_meter_channels> rms{};    // linear full scale
};

inline float to_dbfs(float linear) { return linear > 1e-6f ? 20.0f * std::log10(linear) : -120.0f; }

class LevelMeter {
public:
    static constexpr double window_seconds = 0.1;

    LevelMeter(double sample_rate, int channels)
        : window_frames_(std::max(1, static_cast<int>(std::lround(sample_rate * window_seconds)))),
          channels_(std::clamp(channels, 1, max_meter_channels)),
          windows_(32) {}

    // outputs[c][0..frames) are the block just rendered; end_frame is the stream frame after it.
    void measure(int frames, const float* const* outputs, std::uint64_t end_frame) noexcept {
        int start = 0;
        while (start < frames) {
            const int n = std::min(frames - start, window_frames_ - filled_);
            for (int c = 0; c < channels_; ++c) {
                const float* x = outputs[c] + start;
                float peak = peak_[c];
                double sum = sum_squares_[c];
                for (int k = 0; k < n; ++k) {
                    peak = std::max(peak, std::fabs(x[k]));
                    sum += static_cast<double>(x[k]) * x[k];
                }
                peak_[c] = peak;
                sum_squares_[c] = sum;
            }
            start += n;
            filled_ += n;
            if (filled_ == window_frames_) {
                MeterWindow w;
                w.frame = end_frame - static_cast<std::uint64_t>(frames - start);
                w.channels = channels_;
                for (int c = 0; c < channels_; ++c) {
                    w.peak[c] = peak_[c];
                    w.rms[c] = static_cast<float>(std::sqrt(sum_squares_[c] / window_frames_));
                    peak_[c] = 0.0f;
                    sum_squares_[c] = 0.0;
                }
                windows_.try_push(w);   // full: the control thread is behind; this reading is dropped
                filled_ = 0;
            }
        }
    }

    bool take(MeterWindow& w) noexcept { return windows_.try_pop(w); }
    int window_frames() const { return window_frames_; }

private:
    const int window_frames_;
    const int channels_;
    int filled_ = 0;
    std::array<float, max_meter_channels> peak_{};
    std::array<double, max_meter_channels> sum_squares_{};
    SpscQueue<MeterWindow> windows_;
};

}  // namespace ameoto
