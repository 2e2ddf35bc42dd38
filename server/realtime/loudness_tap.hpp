// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The output's samples, handed from the audio thread to the control thread for /meter's loudness
// (momentary and short-term LUFS, true peak: engine/render/loudness.hpp, libebur128, which allocates and
// so never runs on the audio thread).
//
// Interface:
//   LoudnessTap tap(channels, sample_rate);   // control thread: the ring (1 s) and buffers, allocated once
//   control thread: tap.set_wanted(true)      // only while someone listens (/notify): otherwise the audio
//                                             // thread copies nothing
//                   tap.drain(meter)          // everything waiting, into a LoudnessMeter; frames taken
//                   tap.gaps()                // times the ring was full and a block was left out
//   audio thread:   tap.feed(frames, outputs) // never allocates, locks or blocks: interleaves into a fixed
//                                             // scratch and writes the ring, all or nothing per chunk
//
// When the control thread falls behind (an offline render runs faster than the clock), whole chunks are
// left out and counted; the loudness then covers the samples that came through.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/render/loudness.hpp"
#include "server/realtime/spsc_ring.hpp"

namespace ameoto {

class LoudnessTap {
public:
    static constexpr int chunk_frames = 256;

    LoudnessTap(int channels, double sample_rate)
        : channels_(channels),
          ring_(static_cast<std::size_t>(sample_rate) * static_cast<std::size_t>(channels)),
          scratch_(static_cast<std::size_t>(chunk_frames * channels)),
          out_(static_cast<std::size_t>(chunk_frames * channels) * 16) {}

    void set_wanted(bool wanted) { wanted_.store(wanted, std::memory_order_relaxed); }

    void feed(int frames, const float* const* outputs) noexcept {
        if (!wanted_.load(std::memory_order_relaxed)) return;
        for (int start = 0; start < frames; start += chunk_frames) {
            const int n = frames - start < chunk_frames ? frames - start : chunk_frames;
            for (int i = 0; i < n; ++i)
                for (int c = 0; c < channels_; ++c)
                    scratch_[static_cast<std::size_t>(i * channels_ + c)] = outputs[c][start + i];
            if (!ring_.write(scratch_.data(), static_cast<std::size_t>(n * channels_))) gaps_.fetch_add(1, std::memory_order_relaxed);
        }
    }

    std::size_t drain(LoudnessMeter& meter) {
        std::size_t frames = 0;
        for (;;) {
            const std::size_t got = ring_.read(out_.data(), out_.size());
            if (got == 0) break;
            meter.add(out_.data(), got / static_cast<std::size_t>(channels_));
            frames += got / static_cast<std::size_t>(channels_);
        }
        return frames;
    }

    std::uint64_t gaps() const { return gaps_.load(std::memory_order_relaxed); }

private:
    const int channels_;
    SpscRing<float> ring_;
    std::vector<float> scratch_;   // audio thread's
    std::vector<float> out_;       // control thread's
    std::atomic<bool> wanted_{false};
    std::atomic<std::uint64_t> gaps_{0};
};

}  // namespace ameoto
