// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/partitioned_convolver.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>

namespace ameoto {

namespace {

// FFTW's planner (plan creation and destruction) is not thread-safe; execution is (FFTW 3.3 manual,
// section 5.4). Every plan this program makes goes through this lock, off the audio thread. Never destroyed,
// so a convolver held in a static (a test's, a program's) may still take it while statics are torn down.
std::mutex& fftw_planner_mutex() {
    static std::mutex* const m = new std::mutex;
    return *m;
}

constexpr int convolver_max_block_frames = 8192;
constexpr int convolver_max_channels = 64;

}  // namespace

PartitionedConvolver::PartitionedConvolver(int inputs, int outputs, int block_frames,
                                           const std::vector<std::vector<std::vector<float>>>& filters)
    : inputs_(inputs), outputs_(outputs), block_(block_frames) {
    if (inputs < 1 || inputs > convolver_max_channels || outputs < 1 || outputs > convolver_max_channels)
        throw std::invalid_argument("partitioned convolver: inputs and outputs must be 1.." + std::to_string(convolver_max_channels));
    if (block_frames < 1 || block_frames > convolver_max_block_frames)
        throw std::invalid_argument("partitioned convolver: block of " + std::to_string(block_frames) +
                                    " frames (1.." + std::to_string(convolver_max_block_frames) + ")");
    if (static_cast<int>(filters.size()) != inputs)
        throw std::invalid_argument("partitioned convolver: one filter row per input expected");
    std::size_t longest = 1;
    for (const auto& row : filters) {
        if (static_cast<int>(row.size()) != outputs)
            throw std::invalid_argument("partitioned convolver: one filter per input and output expected");
        for (const auto& h : row) longest = std::max(longest, h.size());
    }
    partitions_ = static_cast<int>((longest + static_cast<std::size_t>(block_) - 1) / static_cast<std::size_t>(block_));
    bins_ = block_ + 1;
    const int K = 2 * block_;
    const auto B = static_cast<std::size_t>(block_);
    const auto bins = static_cast<std::size_t>(bins_);
    const auto P = static_cast<std::size_t>(partitions_);

    {
        std::lock_guard<std::mutex> lock(fftw_planner_mutex());
        time_ = static_cast<float*>(fftwf_malloc(sizeof(float) * static_cast<std::size_t>(K)));
        freq_ = static_cast<float*>(fftwf_malloc(sizeof(fftwf_complex) * bins));
        if (!time_ || !freq_) {
            fftwf_free(time_);
            fftwf_free(freq_);
            throw std::bad_alloc();
        }
        // FFTW_ESTIMATE: the plan is chosen by FFTW's heuristics, not by timing, so the same build gives the
        // same plan (and the same bits) on every run; measuring would cost seconds at start for a few percent.
        forward_ = fftwf_plan_dft_r2c_1d(K, time_, reinterpret_cast<fftwf_complex*>(freq_), FFTW_ESTIMATE);
        inverse_ = fftwf_plan_dft_c2r_1d(K, reinterpret_cast<fftwf_complex*>(freq_), time_, FFTW_ESTIMATE);
        if (!forward_ || !inverse_) {
            if (forward_) fftwf_destroy_plan(static_cast<fftwf_plan>(forward_));
            if (inverse_) fftwf_destroy_plan(static_cast<fftwf_plan>(inverse_));
            fftwf_free(time_);
            fftwf_free(freq_);
            throw std::runtime_error("partitioned convolver: FFTW could not plan a transform of " + std::to_string(K));
        }
    }

    history_.assign(static_cast<std::size_t>(inputs_) * 2 * B, 0.0f);
    x_re_.assign(static_cast<std::size_t>(inputs_) * P * bins, 0.0f);
    x_im_.assign(x_re_.size(), 0.0f);
    h_re_.assign(static_cast<std::size_t>(outputs_) * static_cast<std::size_t>(inputs_) * P * bins, 0.0f);
    h_im_.assign(h_re_.size(), 0.0f);
    y_re_.assign(bins, 0.0f);
    y_im_.assign(bins, 0.0f);

    // The filters' partition spectra (the plans' own buffers are free until process() runs).
    const float scale = 1.0f / static_cast<float>(K);
    for (int c = 0; c < inputs_; ++c)
        for (int o = 0; o < outputs_; ++o) {
            const auto& h = filters[static_cast<std::size_t>(c)][static_cast<std::size_t>(o)];
            for (std::size_t p = 0; p < P; ++p) {
                std::fill(time_, time_ + K, 0.0f);
                const std::size_t first = p * B;
                for (std::size_t t = 0; t < B && first + t < h.size(); ++t) time_[t] = h[first + t];
                fftwf_execute(static_cast<fftwf_plan>(forward_));
                const std::size_t at = ((static_cast<std::size_t>(o) * static_cast<std::size_t>(inputs_) +
                                         static_cast<std::size_t>(c)) * P + p) * bins;
                for (std::size_t k = 0; k < bins; ++k) {
                    h_re_[at + k] = freq_[2 * k] * scale;
                    h_im_[at + k] = freq_[2 * k + 1] * scale;
                }
            }
        }
}

PartitionedConvolver::~PartitionedConvolver() {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    fftwf_destroy_plan(static_cast<fftwf_plan>(forward_));
    fftwf_destroy_plan(static_cast<fftwf_plan>(inverse_));
    fftwf_free(time_);
    fftwf_free(freq_);
}

void PartitionedConvolver::reset() {
    std::fill(history_.begin(), history_.end(), 0.0f);
    std::fill(x_re_.begin(), x_re_.end(), 0.0f);
    std::fill(x_im_.begin(), x_im_.end(), 0.0f);
    newest_ = 0;
}

void PartitionedConvolver::process(const float* const* in, float* const* out) {
    const auto B = static_cast<std::size_t>(block_);
    const auto bins = static_cast<std::size_t>(bins_);
    const auto P = static_cast<std::size_t>(partitions_);
    newest_ = (newest_ + 1) % partitions_;
    const auto slot = static_cast<std::size_t>(newest_);

    // Each input: slide its two-block window, transform it into the ring's newest slot.
    for (std::size_t c = 0; c < static_cast<std::size_t>(inputs_); ++c) {
        float* window = &history_[c * 2 * B];
        std::memmove(window, window + B, B * sizeof(float));
        std::memcpy(window + B, in[c], B * sizeof(float));
        std::memcpy(time_, window, 2 * B * sizeof(float));
        fftwf_execute(static_cast<fftwf_plan>(forward_));
        float* re = &x_re_[(c * P + slot) * bins];
        float* im = &x_im_[(c * P + slot) * bins];
        for (std::size_t k = 0; k < bins; ++k) {
            re[k] = freq_[2 * k];
            im[k] = freq_[2 * k + 1];
        }
    }

    // Each output: the sum over inputs and partitions, p blocks old against partition p.
    for (std::size_t o = 0; o < static_cast<std::size_t>(outputs_); ++o) {
        float* __restrict yr = y_re_.data();
        float* __restrict yi = y_im_.data();
        std::fill(yr, yr + bins, 0.0f);
        std::fill(yi, yi + bins, 0.0f);
        for (std::size_t c = 0; c < static_cast<std::size_t>(inputs_); ++c)
            for (std::size_t p = 0; p < P; ++p) {
                const std::size_t age = (slot + P - p) % P;
                const float* __restrict xr = &x_re_[(c * P + age) * bins];
                const float* __restrict xi = &x_im_[(c * P + age) * bins];
                const std::size_t at = ((o * static_cast<std::size_t>(inputs_) + c) * P + p) * bins;
                const float* __restrict hr = &h_re_[at];
                const float* __restrict hi = &h_im_[at];
                for (std::size_t k = 0; k < bins; ++k) {
                    yr[k] += xr[k] * hr[k] - xi[k] * hi[k];
                    yi[k] += xr[k] * hi[k] + xi[k] * hr[k];
                }
            }
        for (std::size_t k = 0; k < bins; ++k) {
            freq_[2 * k] = yr[k];
            freq_[2 * k + 1] = yi[k];
        }
        fftwf_execute(static_cast<fftwf_plan>(inverse_));
        std::memcpy(out[o], time_ + B, B * sizeof(float));
    }
}

}  // namespace ameoto
