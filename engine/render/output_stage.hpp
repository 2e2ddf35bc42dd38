// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The last stage before the samples leave the engine: the listening gain and the look-ahead limiter,
// the same for every backend (JACK, null, `ameoto render scene`), for any number of channels.
//
// Interface:
//   OutputStage stage(OutputStageConfig{...});   // allocates its delay line once (any thread)
//   audio thread:  stage.set_gain_db(db);        // the listening gain; ramps there over ramp_seconds
//                  stage.process_frame(frame);   // frame[0..channels) in place, one sample of every channel
//                  stage.clipped()               // samples that left the stage past full scale (|x| > 1)
//                  stage.latency_frames()        // the limiter's delay (0 when it is off): look-ahead - 1 + 6
//   process_frame never allocates, frees, locks, blocks or logs.
//
// Calibration: the engine's samples are physical, 1.0 = full_scale_pa at the listener (100 Pa, so 0 dBFS
// is 20 log10(100 / 20e-6) = 133.98 dB SPL); the gain moves that by -gain_db: full_scale_spl_db().
// Identity: gain 0 dB, not ramping, limiter off: the samples pass unchanged, bit for bit.
//
// Gain ramp: a change glides exponentially in amplitude (linearly in dB) over ramp_seconds (50 ms), so a
// jump of any size makes no click (the output's slope is the signal's own plus the ramp's, which over
// 2400 samples is small; tests/engine/render/output_stage_test.cpp).
//
// Limiter (linked over all channels, so the image does not move): the gain needed at each frame is
// r = min(1, ceiling / max_c |x_c|). Its minimum over the last L frames (the look-ahead) is held, then
// released exponentially towards 1 (release_seconds), then smoothed by an L-frame moving average; the
// samples are delayed by L-1 frames. Every average that reaches a delayed frame covers only held values that
// include that frame's own requirement, so the gain applied is never above it: the output stays at or under
// the ceiling by construction (attack: L frames, a linear-in-amplitude slope with no corner to click).
// A final comparison catches rounding (counted in limited_by_clamp, expected 0).
// True peak: max_c |x_c| is taken over the samples and the points between them, interpolated at a
// quarter, a half and three quarters of each interval (4x oversampling, as ITU-R BS.1770-4 Annex 2
// measures true peak) with libebur128's own interpolator, so the stage limits what the meters read: a
// sinc under a Hann window 12 samples wide (its 49 taps at 4x), each phase scaled to DC gain 1. A
// frame's requirement covers both intervals it bounds. Between samples a band-limited signal can peak
// 3 dB above them (a sine at a quarter of the rate, 45 degrees off its samples); the sample-peak limiter
// this replaces let EBU R 128's -1 dBTP pass by 0.1 dB in the cloudburst and by 2 dB on such a sine.
// The interpolation needs 6 samples after the interval: the samples wait 6 frames more (latency_frames).
// Defaults: ceiling -1 dBTP (EBU R 128's maximum true peak), look-ahead and attack 2 ms, release 100 ms.

#include <cstdint>
#include <vector>

namespace ameoto {

struct OutputStageConfig {
    int channels = 2;                    // 1..max_channels
    double sample_rate = 48000.0;        // Hz
    double gain_db = 0.0;                // listening gain at start
    bool limiter = false;
    double ceiling_dbfs = -1.0;          // the limiter's ceiling, dBFS sample peak
    double lookahead_seconds = 0.002;    // look-ahead = attack
    double release_seconds = 0.1;        // time constant of the release
    double ramp_seconds = 0.05;          // a gain change's glide
};

// The physical calibration: 0 dBFS in dB SPL at the listener for full scale = full_scale_pa, less the gain.
double full_scale_spl_db(double full_scale_pa, double gain_db);

class OutputStage {
public:
    static constexpr int max_channels = 16;
    static constexpr int true_peak_lag = 6;   // frames the interpolation waits for
    static constexpr double min_gain_db = -80.0, max_gain_db = 80.0;   // the listening gain's bounds (/gain)

    explicit OutputStage(const OutputStageConfig& config);

    void set_gain_db(double db);              // ramps; clamped to the bounds (callers validate first)
    double gain_db() const { return target_db_; }
    void process_frame(float* frame);
    std::uint64_t clipped() const { return clipped_; }
    std::uint64_t limited_by_clamp() const { return clamped_; }
    int latency_frames() const { return config_.limiter ? lookahead_ - 1 + true_peak_lag : 0; }
    int lookahead_frames() const { return lookahead_; }   // L: the attack and the gain's averaging length
    const OutputStageConfig& config() const { return config_; }
    float reduction() const { return reduction_; }   // the limiter's gain on the frame just out (1: none)
    bool identity() const { return !config_.limiter && gain_ == 1.0 && ramp_left_ == 0; }

private:
    float limit(float* frame);
    float true_peak_need(const float* frame);   // this frame into the history; the need of the frame 6 back

    static constexpr int history_frames = 16;   // >= 2 x true_peak_lag + 1, a power of two
    static constexpr int taps = 12;
    float interpolate_[3][taps] = {};            // phases 1/4, 1/2, 3/4; taps for x[m-5..m+6]
    float tap_gain_ = 1.0f;                      // sum |taps| over the worst phase: the bound for skipping
    OutputStageConfig config_;
    int channels_;
    // gain
    double target_db_ = 0.0;
    double gain_ = 1.0;              // linear, now
    double step_ = 1.0;              // per-frame factor while ramping
    double target_ = 1.0;
    int ramp_left_ = 0;
    int ramp_frames_ = 1;
    // limiter
    std::vector<float> history_;     // the last history_frames input frames x channels
    std::int64_t input_frame_ = 0;
    float previous_interval_ = 0.0f; // the true peak between the frame being limited and the one before
    int lookahead_ = 1;              // L frames
    float ceiling_ = 1.0f;
    double release_coefficient_ = 0.0;
    std::vector<float> delay_;       // L frames x channels
    std::vector<float> hold_value_;  // monotonic deque of (r, frame) over the last L frames
    std::vector<std::int64_t> hold_frame_;
    int hold_head_ = 0, hold_count_ = 0;
    std::vector<double> average_;    // the last L envelope values
    double average_sum_ = 0.0;
    double envelope_ = 1.0;
    int position_ = 0;               // in delay_ and average_
    std::int64_t frame_ = 0;
    std::uint64_t clipped_ = 0;
    std::uint64_t clamped_ = 0;
    float reduction_ = 1.0f;
};

}  // namespace ameoto
