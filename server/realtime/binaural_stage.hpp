// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The live stream's binaural step (--format binaural): one BinauralDecoder (engine/render/binaural_decoder.hpp)
// with the AmbiX bus the renderer writes into, both sized for one block size. The audio bridge renders
// into bus(), then decode() turns it into the two ears (the backend's two ports or the WAV's two channels).
//
// Interface:
//   control or worker thread (it reads a SOFA file, allocates, takes FFTW's planner lock; 0.2-2 s):
//     BinauralStage::Made m = BinauralStage::create(sofa_path, order, rate_hz, block_frames);
//     if (!m.stage) report(m.error);
//   audio thread (AudioBridge::process): never allocates, frees, locks, blocks or logs
//     renderer.process(frames, stage.bus());   // frames <= block_frames()
//     stage.decode(frames, left, right);       // left, right: `frames` samples each
//   any thread: block_frames(), bus_channels(), filter_frames(), rejected_blocks()
//   The destructor runs off the audio thread (the bridge hands a replaced stage back to be freed).
//
// Whole blocks: the decoder's partitioned convolution takes blocks of exactly block_frames() (a JACK
// period, the null backend's --block). A shorter block (the null backend's last block of a --duration
// run; a JACK period shrunk by jack_set_buffer_size until a stage of the new size arrives) is decoded
// with the rest of the bus silent, and its first `frames` ears kept: exact for a stream's last block.
// A longer one cannot be decoded by this stage (the bridge renders it in pieces and plays silence).

#include <memory>
#include <string>
#include <vector>

#include "engine/render/binaural_decoder.hpp"

namespace ameoto {

class BinauralStage {
public:
    struct Made {
        std::unique_ptr<BinauralStage> stage;   // null on error
        std::string error;                      // why (the file, what is wrong, what was asked)
    };
    static Made create(const std::string& sofa_path, int order, double rate_hz, int block_frames);

    float* const* bus() { return bus_pointers_.data(); }
    void decode(int frames, float* left, float* right);

    int block_frames() const { return decoder_->block_frames(); }
    int bus_channels() const { return decoder_->channels(); }
    int filter_frames() const { return decoder_->filter_frames(); }
    double crossover_hz() const { return decoder_->crossover_hz(); }
    unsigned long short_blocks() const { return short_blocks_; }   // audio thread's count (for tests)

private:
    BinauralStage() = default;

    std::unique_ptr<BinauralDecoder> decoder_;
    std::vector<std::vector<float>> bus_;   // [acn][frame], block_frames() long
    std::vector<float*> bus_pointers_;
    std::vector<float> left_, right_;       // a short block's whole decoded block
    unsigned long short_blocks_ = 0;
};

}  // namespace ameoto
