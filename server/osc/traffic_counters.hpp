#pragma once
// What the control thread turned away, for the log: datagrams from senders outside --allow (dropped
// without a reply) and commands answered /fail busy (a queue to the audio thread was full).
// /status.reply has a fixed type tag string (docs/PROTOCOL.md), so these live in the log.
//
// Interface:
//   TrafficCounters c;
//   ++c.refused_senders;  ++c.busy;                         // control thread only
//   if (auto line = c.report_if_changed()) log(*line);     // "load: ... since start"; nullopt when unchanged

#include <cstdint>
#include <optional>
#include <string>

namespace ameoto {

struct TrafficCounters {
    std::uint64_t refused_senders = 0;
    std::uint64_t busy = 0;

    std::optional<std::string> report_if_changed() {
        if (refused_senders == reported_refused_ && busy == reported_busy_) return std::nullopt;
        reported_refused_ = refused_senders;
        reported_busy_ = busy;
        return report();
    }
    std::string report() const {
        return "load: " + std::to_string(busy) + " commands answered /fail busy, " + std::to_string(refused_senders) +
               " datagrams dropped from senders outside --allow, since start";
    }

private:
    std::uint64_t reported_refused_ = 0;
    std::uint64_t reported_busy_ = 0;
};

}  // namespace ameoto
