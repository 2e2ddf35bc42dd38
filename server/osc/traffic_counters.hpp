// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the control thread turned away, for the log: datagrams from senders outside --allow (dropped
// without a reply) and commands answered /fail busy (a queue to the audio thread was full, or, for
// `unread`, the backlog of datagrams read but not yet handled: refused by their address, undecoded).
// /status.reply has a fixed type tag string (docs/PROTOCOL.md), so these live in the log.
//
// Interface:
//   TrafficCounters c;
//   ++c.refused_senders;  ++c.busy;  ++c.unread;            // control thread only (unread is part of busy)
//   if (auto line = c.report_if_changed()) log(*line);     // "load: ... since start"; nullopt when unchanged

#include <cstdint>
#include <optional>
#include <string>

namespace ameoto {

struct TrafficCounters {
    std::uint64_t refused_senders = 0;
    std::uint64_t busy = 0;
    std::uint64_t unread = 0;

    std::optional<std::string> report_if_changed() {
        if (refused_senders == reported_refused_ && busy == reported_busy_) return std::nullopt;   // unread is part of busy
        reported_refused_ = refused_senders;
        reported_busy_ = busy;
        return report();
    }
    std::string report() const {
        return "load: " + std::to_string(busy) + " commands answered /fail busy, " + std::to_string(refused_senders) +
               " datagrams dropped from senders outside --allow, since start" +
               (unread > 0 ? " (" + std::to_string(unread) + " of the busy refused unread: the backlog was full)" : std::string());
    }

private:
    std::uint64_t reported_refused_ = 0;
    std::uint64_t reported_busy_ = 0;
};

}  // namespace ameoto
