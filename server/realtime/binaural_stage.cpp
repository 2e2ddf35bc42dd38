// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/realtime/binaural_stage.hpp"

#include <algorithm>
#include <cmath>

namespace ameoto {

BinauralStage::Made BinauralStage::create(const std::string& sofa_path, int order, double rate_hz, int block_frames, bool limiter) {
    Made made;
    auto d = BinauralDecoder::create(sofa_path, order, rate_hz, block_frames);
    if (!d.decoder) {
        made.error = d.error;
        return made;
    }
    std::unique_ptr<BinauralStage> s(new BinauralStage);
    s->decoder_ = std::move(d.decoder);
    const auto block = static_cast<std::size_t>(block_frames);
    s->bus_.assign(static_cast<std::size_t>(s->decoder_->channels()), std::vector<float>(block, 0.0f));
    for (auto& channel : s->bus_) s->bus_pointers_.push_back(channel.data());
    s->left_.assign(block, 0.0f);
    s->right_.assign(block, 0.0f);
    if (limiter) {
        OutputStageConfig ears;   // the renderer's limiter settings (its defaults), on the two ears, no gain
        ears.channels = 2;
        ears.sample_rate = rate_hz;
        ears.limiter = true;
        s->limiter_ = std::make_unique<OutputStage>(ears);
    }
    made.stage = std::move(s);
    return made;
}

int BinauralStage::decode(int frames, float* left, float* right) {
    const int block = decoder_->block_frames();
    if (frames == block) {
        decoder_->process(bus_pointers_.data(), block, left, right);
        return limit(frames, left, right);
    }
    // A short block: the rest of the bus is silence (the renderer wrote only `frames`), the whole block is
    // decoded and its first `frames` kept. frames > block never comes here (AudioBridge::process).
    ++short_blocks_;
    const int n = std::clamp(frames, 0, block);
    for (auto& channel : bus_) std::fill(channel.begin() + n, channel.end(), 0.0f);
    decoder_->process(bus_pointers_.data(), block, left_.data(), right_.data());
    std::copy(left_.begin(), left_.begin() + n, left);
    std::copy(right_.begin(), right_.begin() + n, right);
    return limit(n, left, right);
}

int BinauralStage::limit(int frames, float* left, float* right) {
    int over = 0;
    for (int i = 0; i < frames; ++i) {
        if (limiter_) {
            float frame[2] = {left[i], right[i]};
            limiter_->process_frame(frame);
            left[i] = frame[0];
            right[i] = frame[1];
        }
        over += (std::fabs(left[i]) > 1.0f) + (std::fabs(right[i]) > 1.0f);
    }
    return over;
}

}  // namespace ameoto
