// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/output_stage.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {

double full_scale_spl_db(double full_scale_pa, double gain_db) {
    constexpr double reference_pa = 20e-6;   // 0 dB SPL (ISO 1683)
    return 20.0 * std::log10(full_scale_pa / reference_pa) - gain_db;
}

OutputStage::OutputStage(const OutputStageConfig& config) : config_(config), channels_(config.channels) {
    if (channels_ < 1 || channels_ > max_channels) throw std::invalid_argument("output stage: channels must be 1 to 16");
    if (!(config.sample_rate > 0.0)) throw std::invalid_argument("output stage: the sample rate must be positive");
    if (!(config.ceiling_dbfs <= 0.0 && config.ceiling_dbfs >= -60.0))
        throw std::invalid_argument("output stage: the ceiling must be -60..0 dBFS");
    ramp_frames_ = std::max(1, static_cast<int>(std::lround(config.ramp_seconds * config.sample_rate)));
    lookahead_ = std::max(1, static_cast<int>(std::lround(config.lookahead_seconds * config.sample_rate)));
    ceiling_ = static_cast<float>(std::pow(10.0, config.ceiling_dbfs / 20.0));
    release_coefficient_ = 1.0 - std::exp(-1.0 / std::max(1.0, config.release_seconds * config.sample_rate));
    if (config_.limiter) {
        history_.assign(static_cast<std::size_t>(history_frames * channels_), 0.0f);
        // The interpolator: x(m + phase) = sum_j x[m + j] h(phase - j), j = -5..6, h a sinc under a Hann
        // window 13 samples wide, each phase's taps scaled to sum to 1 (a DC at the ceiling stays there).
        constexpr double pi = 3.14159265358979323846;
        for (int p = 0; p < 3; ++p) {
            const double phase = 0.25 * (p + 1);
            double sum = 0.0, magnitude = 0.0;
            double h[taps];
            for (int k = 0; k < taps; ++k) {
                const double t = phase - (k - (taps / 2 - 1));
                const double sinc = std::sin(pi * t) / (pi * t);
                const double window = std::cos(pi * t / taps) * std::cos(pi * t / taps);
                h[k] = sinc * window;
                sum += h[k];
            }
            for (int k = 0; k < taps; ++k) {
                interpolate_[p][k] = static_cast<float>(h[k] / sum);
                magnitude += std::fabs(h[k] / sum);
            }
            tap_gain_ = std::max(tap_gain_, static_cast<float>(magnitude));
        }
        delay_.assign(static_cast<std::size_t>(lookahead_ * channels_), 0.0f);
        hold_value_.assign(static_cast<std::size_t>(lookahead_), 1.0f);
        hold_frame_.assign(static_cast<std::size_t>(lookahead_), 0);
        average_.assign(static_cast<std::size_t>(lookahead_), 1.0);
        average_sum_ = lookahead_;
    }
    const double db = std::clamp(config.gain_db, min_gain_db, max_gain_db);
    target_db_ = db;
    gain_ = target_ = std::pow(10.0, db / 20.0);
}

void OutputStage::set_gain_db(double db) {
    db = std::clamp(db, min_gain_db, max_gain_db);
    target_db_ = db;
    target_ = std::pow(10.0, db / 20.0);
    if (target_ == gain_) {
        ramp_left_ = 0;
        return;
    }
    // Exponential in amplitude: equal dB steps each frame, from wherever a ramp in progress has got to.
    step_ = std::pow(target_ / gain_, 1.0 / ramp_frames_);
    ramp_left_ = ramp_frames_;
}

// Writes `frame` into the history (it becomes the newest, n) and returns the true peak around frame
// m = n - 6 over every channel: its sample, and the interpolated points of the intervals (m-1, m) and
// (m, m+1); the latter needs x[m-5..m+6], the newest six frames after m. `frame` is then overwritten
// with x[m], the frame the limiter goes on with.
float OutputStage::true_peak_need(const float* frame) {
    constexpr int mask = history_frames - 1;
    const std::size_t C = static_cast<std::size_t>(channels_);
    const int n = static_cast<int>(input_frame_ & mask);
    for (std::size_t c = 0; c < C; ++c) history_[static_cast<std::size_t>(n) * C + c] = frame[c];
    ++input_frame_;
    const int m = (n - true_peak_lag) & mask;
    auto at = [&](int offset, std::size_t c) { return history_[static_cast<std::size_t>((m + offset) & mask) * C + c]; };
    float sample = 0.0f, window = 0.0f;
    for (std::size_t c = 0; c < C; ++c) {
        sample = std::max(sample, std::fabs(at(0, c)));
        for (int j = 1 - taps / 2; j <= taps / 2; ++j) window = std::max(window, std::fabs(at(j, c)));
    }
    // No point between can pass the ceiling when every tap's sample is small enough: skip the sums.
    float interval = 0.0f;
    if (window * tap_gain_ > ceiling_) {
        for (std::size_t c = 0; c < C; ++c)
            for (int p = 0; p < 3; ++p) {
                float v = 0.0f;
                for (int k = 0; k < taps; ++k) v += interpolate_[p][k] * at(k - (taps / 2 - 1), c);
                interval = std::max(interval, std::fabs(v));
            }
    }
    const float peak = std::max({sample, interval, previous_interval_});
    previous_interval_ = interval;
    return peak;
}

float OutputStage::limit(float* frame) {
    const float peak = true_peak_need(frame);
    {
        constexpr int mask = history_frames - 1;
        const int m = static_cast<int>((input_frame_ - 1 - true_peak_lag) & mask);
        for (int c = 0; c < channels_; ++c) frame[c] = history_[static_cast<std::size_t>(m * channels_ + c)];
    }
    // The gain this frame needs, a millionth under (0.00001 dB) so that float rounding of x g cannot carry a
    // sample past the ceiling.
    const float need = peak > ceiling_ ? static_cast<float>(static_cast<double>(ceiling_) / peak * (1.0 - 1e-6)) : 1.0f;
    const int L = lookahead_;
    // The smallest requirement of the last L frames: a monotonic queue (values rise from head to tail).
    while (hold_count_ > 0 && hold_frame_[static_cast<std::size_t>(hold_head_)] <= frame_ - L) {
        hold_head_ = (hold_head_ + 1) % L;
        --hold_count_;
    }
    while (hold_count_ > 0 && hold_value_[static_cast<std::size_t>((hold_head_ + hold_count_ - 1) % L)] >= need) --hold_count_;
    const int tail = (hold_head_ + hold_count_) % L;
    hold_value_[static_cast<std::size_t>(tail)] = need;
    hold_frame_[static_cast<std::size_t>(tail)] = frame_;
    ++hold_count_;
    const double held = hold_value_[static_cast<std::size_t>(hold_head_)];
    // Down at once to the held value, back up towards 1 with the release's time constant.
    envelope_ = std::min(held, envelope_ + (1.0 - envelope_) * release_coefficient_);
    const std::size_t at = static_cast<std::size_t>(position_);
    average_sum_ += envelope_ - average_[at];
    average_[at] = envelope_;
    for (int c = 0; c < channels_; ++c) delay_[at * static_cast<std::size_t>(channels_) + static_cast<std::size_t>(c)] = frame[c];
    position_ = (position_ + 1) % L;
    if (position_ == 0) {   // a fresh sum every L frames: no drift over hours
        average_sum_ = 0.0;
        for (double v : average_) average_sum_ += v;
    }
    ++frame_;
    // The frame written L-1 frames ago is in the slot written next (L = 1: the one just written).
    const std::size_t out = static_cast<std::size_t>(L == 1 ? 0 : position_) * static_cast<std::size_t>(channels_);
    const double gain = average_sum_ / L;
    float reduction = 1.0f;
    for (int c = 0; c < channels_; ++c) {
        float y = static_cast<float>(delay_[out + static_cast<std::size_t>(c)] * gain);
        if (std::fabs(y) > ceiling_) {   // rounding only: the average is never above the need
            y = std::copysign(ceiling_, y);
            ++clamped_;
        }
        frame[c] = y;
    }
    reduction = static_cast<float>(gain);
    return reduction;
}

void OutputStage::process_frame(float* frame) {
    if (ramp_left_ > 0) {
        gain_ *= step_;
        if (--ramp_left_ == 0) gain_ = target_;
    }
    if (gain_ != 1.0)
        for (int c = 0; c < channels_; ++c) frame[c] = static_cast<float>(frame[c] * gain_);
    if (config_.limiter) reduction_ = limit(frame);
    for (int c = 0; c < channels_; ++c)
        if (std::fabs(frame[c]) > 1.0f) ++clipped_;
}

}  // namespace ameoto
