// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Loudness after EBU R 128 / ITU-R BS.1770-4 (K-weighting, 400 ms momentary and 3 s short-term windows,
// gated integration), measured with libebur128 (MIT licence; Debian's libebur128-dev).
//
// Interface:
//   LoudnessMeter m(channels, sample_rate, LoudnessMeter::integrated | LoudnessMeter::peaks);   // allocates
//   m.add(interleaved, frames);          // frames of `channels` floats each
//   m.integrated_lufs()                  // gated integrated loudness; -inf below the -70 LUFS gate
//   m.momentary_lufs(), m.short_term_lufs(), m.true_peak_dbfs(), m.sample_peak_dbfs()
//   integrated_lufs(samples, channels, sample_rate)   // one call for a whole render
//
// Threads: any, but never the audio thread: libebur128 allocates (its integrated mode keeps a list of
// blocks), so the server feeds it on the control thread (server/realtime/loudness_tap.hpp carries the samples).
// Channels: every channel is weighted 1 (BS.1770's weight for left, right and centre), so a ring of
// speakers or a mono stream counts each channel's power as it is played.

#include <cstddef>
#include <vector>

namespace ameoto {

class LoudnessMeter {
public:
    enum Mode : int { short_term = 1, integrated = 2, peaks = 4 };
    LoudnessMeter(int channels, double sample_rate, int modes);
    ~LoudnessMeter();
    LoudnessMeter(const LoudnessMeter&) = delete;
    LoudnessMeter& operator=(const LoudnessMeter&) = delete;

    void add(const float* interleaved, std::size_t frames);
    int channels() const { return channels_; }
    double integrated_lufs() const;      // needs `integrated`
    double momentary_lufs() const;       // the last 400 ms
    double short_term_lufs() const;      // the last 3 s; needs `short_term`
    double true_peak_dbfs() const;       // since the last reset_peaks(), the largest over channels (libebur128's oversampled true peak)
    double sample_peak_dbfs() const;
    void reset_peaks();                  // peaks from now on (a /meter window's)

private:
    void* state_ = nullptr;   // ebur128_state* (an anonymous struct in ebur128.h: cannot be declared here)
    int channels_;
    int modes_;
    double window_true_peak_ = 0.0, window_sample_peak_ = 0.0;   // linear, since the last reset_peaks()
};

// Whole-buffer integrated loudness, LUFS (-inf when the buffer is silent or below the absolute gate).
double integrated_lufs(const std::vector<float>& interleaved, int channels, double sample_rate);
// Whole-buffer integrated loudness of a signal of any level: it is measured scaled to about -20 dBFS RMS
// and the scale taken back out (the gate at -70 LUFS would otherwise drop a quiet scene such as the pond,
// whose physical level is near -105 LUFS). -inf for silence.
double integrated_lufs_any_level(const std::vector<float>& interleaved, int channels, double sample_rate);

}  // namespace ameoto
