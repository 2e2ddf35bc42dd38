// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --block-trace FILE: every audio callback's record (wall and CPU time, faults, what it did) taken
// from the bridge's ring and the slow or late ones written to FILE (realtime/block_trace.hpp says
// what each column means; docs/bench.md, "Slow blocks", how to read one).
//
// Interface:
//   BlockTracing tracing(bridge);
//   if (!tracing.open(options, sample_rate)) return 1;   // before audio starts; without --block-trace: off, true
//   tracing.drain();      // each poll (5 ms)
//   tracing.finish();     // after the backend stopped: the rest, the file's summary, one log line
//
// Thread: the control thread (the one reader of the ring), and the main thread after the loop.

#include <memory>

#include "server/options.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/block_trace.hpp"

namespace ameoto {

class BlockTracing {
public:
    static constexpr std::size_t ring_records = 16384;   // 22 s of 64-frame callbacks: the poll can fall far behind

    explicit BlockTracing(AudioBridge& bridge) : bridge_(bridge) {}
    bool open(const DaemonOptions& options, double sample_rate);
    void drain();
    void finish();

private:
    AudioBridge& bridge_;
    std::unique_ptr<BlockTraceFile> file_;   // null when off
};

}  // namespace ameoto
