// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A multichannel uniformly partitioned overlap-save convolver (UPOLS) with a frequency-domain delay line:
// `inputs` signals, `outputs` sums, out_o = sum_c in_c * h[c][o], one block of `block_frames` at a time,
// with no latency beyond the filters' own (each call's output is that call's input convolved).
//
// Interface:
//   PartitionedConvolver conv(inputs, outputs, block_frames, filters);   // filters[c][o]: taps (any length)
//   audio thread:  conv.process(in, out);    // in[c][0..block_frames), out[o][0..block_frames) overwritten
//                  conv.reset();             // forget the past (silence in, silence out)
//   any thread:    conv.partitions(), conv.block_frames()
// Threads: the constructor and destructor make and destroy FFTW plans, which FFTW's planner does not allow
// from two threads at once: they hold one process-wide mutex, and so must never run on the audio thread.
// process() and reset() never allocate, free, lock, block or log: fftwf_execute_dft_r2c/c2r on the
// plan's own preallocated, aligned buffers is documented as thread-safe and allocation-free (FFTW 3.3
// manual, "Thread safety" and "New-array Execute Functions"); the test suite's probe checks it.
//
// Method (Wefers 2015, "Partitioned convolution algorithms for real-time auralization", ch. 5; Stockham
// 1966): each filter is cut into P = ceil(L / B) partitions of B taps, each zero-padded to K = 2B and
// transformed once (scaled by 1/K, FFTW being unnormalised). Per block, each input's last 2B samples are
// transformed once (X_c), kept in a ring of the last P spectra; each output's spectrum is
// Y_o = sum_c sum_p X_c[t - p] H[c][o][p], transformed back once, and its last B samples are the block
// (the first B carry the circular wrap, discarded: overlap-save). Cost per block: `inputs` forward and
// `outputs` inverse real FFTs of 2B points and inputs * outputs * P * (B + 1) complex multiply-adds.
// Spectra are stored split (real and imaginary arrays) so the multiply-add loop vectorises.
// Exactness: the result equals direct convolution up to float rounding (about 1e-6 relative; tested
// against a double direct convolution for blocks of 64, 256 and 1024).

#include <vector>

namespace ameoto {

class PartitionedConvolver {
public:
    PartitionedConvolver(int inputs, int outputs, int block_frames,
                         const std::vector<std::vector<std::vector<float>>>& filters);   // throws std::invalid_argument
    ~PartitionedConvolver();
    PartitionedConvolver(const PartitionedConvolver&) = delete;
    PartitionedConvolver& operator=(const PartitionedConvolver&) = delete;

    void process(const float* const* in, float* const* out);
    void reset();

    int inputs() const { return inputs_; }
    int outputs() const { return outputs_; }
    int block_frames() const { return block_; }
    int partitions() const { return partitions_; }

private:
    int inputs_, outputs_, block_, partitions_, bins_;
    int newest_ = 0;                     // ring slot of the newest input spectrum
    void* forward_ = nullptr;            // fftwf_plan: time_ (2B reals) -> freq_ (B+1 complex)
    void* inverse_ = nullptr;            // fftwf_plan: freq_ -> time_
    float* time_ = nullptr;              // fftwf_malloc'd, 2B
    float* freq_ = nullptr;              // fftwf_malloc'd, 2 (B+1) interleaved
    std::vector<float> history_;         // [c][2B]: the last two blocks of each input
    std::vector<float> x_re_, x_im_;     // [c][p][bin]: ring of input spectra
    std::vector<float> h_re_, h_im_;     // [o][c][p][bin]: filter partitions' spectra, scaled 1/K
    std::vector<float> y_re_, y_im_;     // [bin]: one output's accumulator
};

}  // namespace ameoto
