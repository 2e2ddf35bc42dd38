// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/binaural_supply.hpp"

#include "server/log_lines.hpp"

namespace ameoto {

BinauralSupply::BinauralSupply(boost::asio::io_context& io, AudioBridge& bridge, std::string sofa_path, int order, double rate_hz, bool limiter)
    : bridge_(bridge),
      sofa_path_(std::move(sofa_path)),
      order_(order),
      rate_hz_(rate_hz),
      limiter_(limiter),
      wanted_(bridge.binaural_block()),
      seen_(bridge.binaural_block()),
      worker_(io) {}

void BinauralSupply::watch(int backend_block) {
    while (bridge_.take_retired_binaural()) {}   // freed here, off the audio thread
    if (waiting_ && bridge_.offer_binaural(waiting_)) ++changes_;
    seen_ = backend_block;
    if (building_ || backend_block <= 0 || backend_block == wanted_) return;
    if (!waiting_ && backend_block == bridge_.binaural_block()) {   // back to the size playing (a change undone)
        wanted_ = backend_block;
        return;
    }
    wanted_ = backend_block;
    building_ = true;
    say("the backend's block size is now " + std::to_string(backend_block) + " frames: building the binaural decoder for it");
    const std::string path = sofa_path_;
    const int order = order_;
    const double rate = rate_hz_;
    const bool limiter = limiter_;
    worker_.submit<BinauralStage::Made>([path, order, rate, backend_block, limiter] {
                                            return BinauralStage::create(path, order, rate, backend_block, limiter);
                                        },
                                        [this, backend_block](BinauralStage::Made made) { built(std::move(made), backend_block); },
                                        [this, backend_block](const std::string& error) {
                                            built(BinauralStage::Made{nullptr, error}, backend_block);
                                        });
}

void BinauralSupply::built(BinauralStage::Made made, int block) {
    building_ = false;
    if (!made.stage) {
        // wanted_ stays: the same size is not tried again until the block size changes once more.
        warn("cannot build the binaural decoder for blocks of " + std::to_string(block) + " frames: " + made.error +
             "; the ears play silence at that block size");
        return;
    }
    if (block != seen_) return;   // the size changed again meanwhile: the next watch builds for the new one
    waiting_ = std::move(made.stage);
    if (bridge_.offer_binaural(waiting_)) ++changes_;
    say("binaural decoder for blocks of " + std::to_string(block) + " frames handed to the audio thread");
}

}  // namespace ameoto
