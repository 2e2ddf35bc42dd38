// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/render_output.hpp"

#include <algorithm>

namespace ameoto::client {

std::optional<RenderOutput> RenderOutput::make(const OutputFormat& format, int bus_channels, const std::string& hrtf_path, int rate,
                                               int block, bool limiter, std::string& error) {
    RenderOutput out;
    out.block_ = block;
    const auto frames = static_cast<std::size_t>(block);
    out.planar_.assign(static_cast<std::size_t>(bus_channels), std::vector<float>(frames, 0.0f));
    out.pointers_.resize(out.planar_.size());
    if (format.kind == OutputKind::binaural) {
        auto made = BinauralDecoder::create(hrtf_path, format.order, rate, block);
        if (!made.decoder) {
            error = "--format binaural: " + made.error;
            return std::nullopt;
        }
        if (made.decoder->channels() != bus_channels) {
            error = "--format binaural: the decoder takes " + std::to_string(made.decoder->channels()) + " channels, the renderer makes " +
                    std::to_string(bus_channels);
            return std::nullopt;
        }
        out.decoder_ = std::move(made.decoder);
        for (const auto& c : out.planar_) out.inputs_.push_back(c.data());
        out.ears_.assign(2, std::vector<float>(frames, 0.0f));
        for (const auto& ear : out.ears_) out.heard_.push_back(ear.data());
        if (limiter) {
            OutputStageConfig ears;   // the renderer's limiter settings (its defaults), on the two ears, no gain
            ears.channels = 2;
            ears.sample_rate = rate;
            ears.limiter = true;
            out.limiter_ = std::make_unique<OutputStage>(ears);
        }
    } else {
        for (const auto& c : out.planar_) out.heard_.push_back(c.data());
    }
    return std::optional<RenderOutput>(std::move(out));   // the vectors' buffers move with it
}

float* const* RenderOutput::bus(int offset) {
    for (std::size_t c = 0; c < planar_.size(); ++c) pointers_[c] = planar_[c].data() + offset;
    return pointers_.data();
}

void RenderOutput::finish(int frames) {
    if (!decoder_) return;
    // The decoder takes whole blocks: a last short block is padded with silence (its tail not written).
    for (auto& p : planar_) std::fill(p.begin() + std::clamp(frames, 0, block_), p.end(), 0.0f);
    decoder_->process(inputs_.data(), block_, ears_[0].data(), ears_[1].data());
    if (!limiter_) return;
    for (int i = 0; i < std::clamp(frames, 0, block_); ++i) {
        const auto n = static_cast<std::size_t>(i);
        float frame[2] = {ears_[0][n], ears_[1][n]};
        limiter_->process_frame(frame);
        ears_[0][n] = frame[0];
        ears_[1][n] = frame[1];
    }
}

}  // namespace ameoto::client
