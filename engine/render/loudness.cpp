// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/loudness.hpp"

#include <ebur128.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ameoto {
namespace {
ebur128_state* st(void* p) { return static_cast<ebur128_state*>(p); }
double to_db(double linear) { return linear > 0.0 ? 20.0 * std::log10(linear) : -std::numeric_limits<double>::infinity(); }
}  // namespace

LoudnessMeter::LoudnessMeter(int channels, double sample_rate, int modes) : channels_(channels), modes_(modes) {
    int m = EBUR128_MODE_M;
    if (modes & short_term) m |= EBUR128_MODE_S;
    if (modes & integrated) m |= EBUR128_MODE_I;
    if (modes & peaks) m |= EBUR128_MODE_TRUE_PEAK | EBUR128_MODE_SAMPLE_PEAK;
    if (channels < 1 || channels > 64 || !(sample_rate >= 8000.0)) throw std::invalid_argument("loudness meter: bad channels or rate");
    ebur128_state* state = ebur128_init(static_cast<unsigned>(channels), static_cast<unsigned long>(std::lround(sample_rate)), m);
    if (!state) throw std::runtime_error("libebur128: cannot make a loudness meter");
    state_ = state;
    for (int c = 0; c < channels; ++c) ebur128_set_channel(state, static_cast<unsigned>(c), EBUR128_LEFT);
}

LoudnessMeter::~LoudnessMeter() {
    ebur128_state* state = st(state_);
    ebur128_destroy(&state);
}

void LoudnessMeter::add(const float* interleaved, std::size_t frames) {
    if (frames == 0) return;
    ebur128_add_frames_float(st(state_), interleaved, frames);
    if (!(modes_ & peaks)) return;
    // ebur128_prev_*_peak covers the last add only: the window's peak is the largest since reset_peaks().
    for (int c = 0; c < channels_; ++c) {
        double v = 0.0;
        if (ebur128_prev_true_peak(st(state_), static_cast<unsigned>(c), &v) == EBUR128_SUCCESS) window_true_peak_ = std::max(window_true_peak_, v);
        if (ebur128_prev_sample_peak(st(state_), static_cast<unsigned>(c), &v) == EBUR128_SUCCESS)
            window_sample_peak_ = std::max(window_sample_peak_, v);
    }
}

double LoudnessMeter::integrated_lufs() const {
    double out = -HUGE_VAL;
    if (!(modes_ & integrated) || ebur128_loudness_global(st(state_), &out) != EBUR128_SUCCESS) return -HUGE_VAL;
    return out;
}

double LoudnessMeter::momentary_lufs() const {
    double out = -HUGE_VAL;
    if (ebur128_loudness_momentary(st(state_), &out) != EBUR128_SUCCESS) return -HUGE_VAL;
    return out;
}

double LoudnessMeter::short_term_lufs() const {
    double out = -HUGE_VAL;
    if (!(modes_ & short_term) || ebur128_loudness_shortterm(st(state_), &out) != EBUR128_SUCCESS) return -HUGE_VAL;
    return out;
}

double LoudnessMeter::true_peak_dbfs() const { return to_db(window_true_peak_); }
double LoudnessMeter::sample_peak_dbfs() const { return to_db(window_sample_peak_); }

void LoudnessMeter::reset_peaks() {
    window_true_peak_ = 0.0;
    window_sample_peak_ = 0.0;
}

double integrated_lufs(const std::vector<float>& interleaved, int channels, double sample_rate) {
    LoudnessMeter m(channels, sample_rate, LoudnessMeter::integrated);
    m.add(interleaved.data(), interleaved.size() / static_cast<std::size_t>(channels));
    return m.integrated_lufs();
}

double integrated_lufs_any_level(const std::vector<float>& interleaved, int channels, double sample_rate) {
    double sum = 0.0;
    for (float x : interleaved) sum += static_cast<double>(x) * x;
    if (!(sum > 0.0)) return -HUGE_VAL;
    const double rms = std::sqrt(sum / static_cast<double>(interleaved.size()));
    const double scale = 0.1 / rms;   // -20 dBFS RMS: far above the gate, far below full scale's float limits
    std::vector<float> scaled(interleaved.size());
    for (std::size_t k = 0; k < interleaved.size(); ++k) scaled[k] = static_cast<float>(interleaved[k] * scale);
    return integrated_lufs(scaled, channels, sample_rate) - 20.0 * std::log10(scale);
}

}  // namespace ameoto
