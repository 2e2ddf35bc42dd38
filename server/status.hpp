// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// /status.reply: the load, the drops, the counters and the clock, as docs/PROTOCOL.md ("Status")
// lists them, and the drops-per-second figure it carries.
//
// Interface:
//   StatusReport status(bridge, backend);
//   std::vector<protocol::OscArgument> fields = status.arguments();   // any thread
//   status.measure_rate();     // control thread, once a second: drops per second since the last call
//
// Threads: arguments() runs on the control thread and on the TCP endpoint's thread (which answers
// /status itself, docs/reliability.md "Load"), so it reads only the audio bridge's atomics, the
// backend's atomics and constants, and the drops-per-second figure (atomic). Each call takes the CPU
// peak since the previous one (AudioBridge::take_cpu_peak_percent), whichever thread asked.

#include <atomic>
#include <cstdint>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "server/backends/backend.hpp"
#include "server/realtime/audio_bridge.hpp"

namespace ameoto {

class StatusReport {
public:
    StatusReport(AudioBridge& bridge, const Backend& backend) : bridge_(bridge), backend_(backend) {}
    std::vector<protocol::OscArgument> arguments();
    void measure_rate();
    int block_size() const { return backend_.block_size(); }

private:
    AudioBridge& bridge_;
    const Backend& backend_;
    std::atomic<double> drops_per_second_{0.0};
    std::uint64_t rate_drops_ = 0, rate_frames_ = 0;   // control thread: at the last measure_rate()
};

}  // namespace ameoto
