// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --format binaural, live: the decoder stages (server/realtime/binaural_stage.hpp) the audio bridge plays
// through, one for each block size the backend runs at. The first is built before audio starts
// (first_stage); when the backend's block size changes (JACK's jack_set_buffer_size_callback, or a
// JACK server that comes back with another buffer size) a stage for the new size is built on a thread of
// its own (libmysofa and FFTW's planner allocate and lock: 0.2-0.4 s once the set is in libmysofa's
// cache) and handed to the audio thread through the bridge's lock-free queue; the stage it replaces
// comes back here to be freed. Until it arrives, blocks of the new size are silence (a longer block) or
// decoded padded (a shorter one): about 0.3 s after a change.
//
// Interface (control thread):
//   auto m = BinauralStage::create(options.hrtf, order, rate_hz, backend.block_size(), limiter);   // the first, for the bridge
//   BinauralSupply supply(io, bridge, options.hrtf, order, rate_hz, limiter);
//   every poll: supply.watch(backend.block_size());   // builds, hands over, frees; logs each change

#include <boost/asio/io_context.hpp>

#include <memory>
#include <string>

#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/binaural_stage.hpp"
#include "server/worker.hpp"

namespace ameoto {

class BinauralSupply {
public:
    BinauralSupply(boost::asio::io_context& io, AudioBridge& bridge, std::string sofa_path, int order, double rate_hz, bool limiter);
    BinauralSupply(const BinauralSupply&) = delete;
    BinauralSupply& operator=(const BinauralSupply&) = delete;

    void watch(int backend_block);
    int changes() const { return changes_; }   // stages handed over after the first

private:
    void built(BinauralStage::Made made, int block);

    AudioBridge& bridge_;
    const std::string sofa_path_;
    const int order_;
    const double rate_hz_;
    const bool limiter_;     // the ears' limiter in every stage built
    int wanted_ = 0;         // the block size last built for (or being built)
    int seen_ = 0;           // the backend's block size at the last watch
    bool building_ = false;
    int changes_ = 0;
    std::unique_ptr<BinauralStage> waiting_;   // built, not yet taken (the handoff queue was full)
    Worker worker_;          // last: joined first, before what its jobs' replies touch goes
};

}  // namespace ameoto
