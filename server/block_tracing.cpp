// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/block_tracing.hpp"

#include <cmath>
#include <string>

#include "server/log_lines.hpp"

namespace ameoto {

bool BlockTracing::open(const DaemonOptions& options, double sample_rate) {
    if (!options.block_trace) return true;
    try {
        file_ = std::make_unique<BlockTraceFile>(*options.block_trace, sample_rate, options.block_trace_threshold);
    } catch (const std::exception& e) {
        warn(std::string("--block-trace: ") + e.what());
        return false;
    }
    bridge_.enable_block_trace(ring_records);
    say("tracing callbacks over " + std::to_string(static_cast<int>(std::lround(100 * options.block_trace_threshold))) +
        " % of the period to " + *options.block_trace);
    return true;
}

void BlockTracing::drain() {
    if (!file_) return;
    BlockRecord record;
    bool wrote = false;
    while (bridge_.block_trace()->pop(record)) wrote |= file_->add(record);
    if (wrote) file_->flush();
}

void BlockTracing::finish() {
    if (!file_) return;
    drain();
    file_->close(bridge_.block_trace()->lost());
    say("block trace: " + std::to_string(file_->blocks()) + " callbacks, slow: " + std::to_string(file_->slow_ours()) + " ours, " +
        std::to_string(file_->slow_machine()) + " the machine's; started late: " + std::to_string(file_->late()));
}

}  // namespace ameoto
