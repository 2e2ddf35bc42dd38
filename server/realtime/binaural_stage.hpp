// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The live stream's binaural step (--format binaural): one BinauralDecoder (engine/render/binaural_decoder.hpp)
// with the AmbiX bus the renderer writes into, both sized for one block size. The audio bridge renders
// into bus(), then decode() turns it into the two ears (the backend's two ports or the WAV's two channels).
//
// Interface:
//   control or worker thread (it reads a SOFA file, allocates, takes FFTW's planner lock; 0.2-2 s):
//     BinauralStage::Made m = BinauralStage::create(sofa_path, order, rate_hz, block_frames, limiter);
//     if (!m.stage) report(m.error);
//   audio thread (AudioBridge::process): never allocates, frees, locks, blocks or logs
//     renderer.process(frames, stage.bus());   // frames <= block_frames()
//     stage.decode(frames, left, right);       // left, right: `frames` samples each; returns the ear
//                                              // samples past full scale (|x| > 1) it wrote
//   any thread: block_frames(), bus_channels(), filter_frames(), latency_frames(), short_blocks()
//   The destructor runs off the audio thread (the bridge hands a replaced stage back to be freed).
//
// Whole blocks: the decoder's partitioned convolution takes blocks of exactly block_frames() (a JACK
// period, the null backend's --block). A shorter block (the null backend's last block of a --duration
// run; a JACK period shrunk by jack_set_buffer_size until a stage of the new size arrives) is decoded
// with the rest of the bus silent, and its first `frames` ears kept: exact for a stream's last block.
// A longer one cannot be decoded by this stage (the bridge renders it in pieces and plays silence).
//
// The limiter (limiter = true: --limiter on, the default with --level auto) acts here, on the two ears:
// the renderer's own output stage runs with its limiter off for a binaural bus (its gain still applied),
// since a limiter on the 16 bus channels does not hold the decoded ears under the ceiling (the decoder
// has a gain of its own, and a source at the side reaches its near ear louder). It is the renderer's
// OutputStage (engine/render/output_stage.hpp) with its defaults: ceiling -1 dBTP, 2 ms look-ahead and
// attack, 100 ms release, linked over both ears; preallocated here, it delays the ears by
// latency_frames() (101 at 48 kHz). A stage built for a new block size starts its limiter afresh.

#include <memory>
#include <string>
#include <vector>

#include "engine/render/binaural_decoder.hpp"
#include "engine/render/output_stage.hpp"

namespace ameoto {

class BinauralStage {
public:
    struct Made {
        std::unique_ptr<BinauralStage> stage;   // null on error
        std::string error;                      // why (the file, what is wrong, what was asked)
    };
    static Made create(const std::string& sofa_path, int order, double rate_hz, int block_frames, bool limiter);

    float* const* bus() { return bus_pointers_.data(); }
    int decode(int frames, float* left, float* right);

    int block_frames() const { return decoder_->block_frames(); }
    int bus_channels() const { return decoder_->channels(); }
    int filter_frames() const { return decoder_->filter_frames(); }
    double crossover_hz() const { return decoder_->crossover_hz(); }
    int latency_frames() const { return limiter_ ? limiter_->latency_frames() : 0; }   // the ear limiter's delay
    const OutputStage* limiter() const { return limiter_.get(); }   // null: off (its counters: audio thread's)
    unsigned long short_blocks() const { return short_blocks_; }   // audio thread's count (for tests)

private:
    BinauralStage() = default;
    int limit(int frames, float* left, float* right);   // and counts the samples past full scale

    std::unique_ptr<BinauralDecoder> decoder_;
    std::vector<std::vector<float>> bus_;   // [acn][frame], block_frames() long
    std::vector<float*> bus_pointers_;
    std::vector<float> left_, right_;       // a short block's whole decoded block
    std::unique_ptr<OutputStage> limiter_;  // the ears' limiter (null: --limiter off)
    unsigned long short_blocks_ = 0;
};

}  // namespace ameoto
