// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the offline renders (render scene, render score) write, block by block: the renderer's channels
// as they are, or, for --format binaural, its AmbiX bus decoded to two ears (engine/render/
// binaural_decoder.hpp), as ameotod's live stream decodes it (server/realtime/binaural_stage.hpp).
//
// Interface:
//   std::string error;
//   auto out = RenderOutput::make(format, renderer.config().channels, hrtf_path, rate, block, limiter, error);
//   if (!out) fail(error);   // binaural: the SOFA file could not be used (it says why)
//   per block of n <= block frames, rendered in one or more pieces:
//     renderer.process(piece, out->bus(offset));   // frames [offset, offset + piece) of the block
//     out->finish(n);                              // binaural: decoded (a short last block padded), limited
//     out->channel(c)[0..n)                        // the file's channel c, c < out->channels()
//
// The decoder takes whole blocks of one size, so the block is the unit here, and a render that cuts its
// engine calls shorter (render score, before a command that would overfill the renderer's pending list)
// renders the pieces into one block: the samples are the same at any cut. Built before the first sample
// (libmysofa reads and resamples the SOFA file: about 2 s the first time at a rate).
//
// The limiter, binaural: `limiter` true runs the renderer's limiter (engine/render/output_stage.hpp, its
// defaults: -1 dBTP, 2 ms look-ahead and attack, 100 ms release) on the two decoded ears, as ameotod's
// live stage does; the caller then builds the renderer with its own limiter off (a limiter on the bus
// does not hold the ears under the ceiling). The ears come out latency_frames() (101 at 48 kHz) late, as
// they do live: the file is the stream. Other formats: `limiter` is ignored (the renderer's limits them).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/render/binaural_decoder.hpp"
#include "engine/render/output_stage.hpp"
#include "engine/scene/output_format.hpp"

namespace ameoto::client {

class RenderOutput {
public:
    static std::optional<RenderOutput> make(const OutputFormat& format, int bus_channels, const std::string& hrtf_path, int rate,
                                            int block, bool limiter, std::string& error);

    float* const* bus(int offset = 0);
    void finish(int frames);
    const float* channel(int c) const { return heard_[static_cast<std::size_t>(c)]; }
    int channels() const { return static_cast<int>(heard_.size()); }
    int block() const { return block_; }
    int latency_frames() const { return limiter_ ? limiter_->latency_frames() : 0; }   // the ears' limiter's

private:
    RenderOutput() = default;

    int block_ = 0;
    std::vector<std::vector<float>> planar_;   // [bus channel][frame]
    std::vector<float*> pointers_;             // bus(offset)'s
    std::vector<std::vector<float>> ears_;     // binaural: [ear][frame]
    std::vector<const float*> heard_;          // the file's channels
    std::vector<const float*> inputs_;         // the decoder's view of the bus
    std::unique_ptr<BinauralDecoder> decoder_;   // binaural only
    std::unique_ptr<OutputStage> limiter_;       // binaural with the limiter on
};

}  // namespace ameoto::client
