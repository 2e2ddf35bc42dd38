// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --start-at: a node's shared start epoch. The nodes of one scene (docs/nodes.md) must begin their rain
// field at the same frame, or their parts, each drawn from the same seed, no longer add up to the whole
// scene. Until the epoch the backend writes silence and does not run the renderer at all (its frame
// counter, its rain and its clock stay at zero); from the first cycle the gate opens on, it plays.
//
// Interface (audio thread only; pure arithmetic, no system call):
//   StartGate gate(start_unix_ns);            // 0: no epoch, open from the first cycle
//   if (gate.open(cycle_unix_ns, period_ns)) render the cycle; else write silence
//   gate.opened() / gate.lag_ns()             // for the log (written by the audio thread, read after)
//
// Which cycle: the first whose first frame plays at or after start - period / 2, i.e. the cycle that
// starts nearest the epoch. cycle_unix_ns is the backend's filtered wall time of the cycle's first frame
// (cycle_clock.hpp: JACK's delay-locked loop), the same figure for every client of one JACK server, so
// nodes on one server given the same epoch open on the same cycle. They could disagree only if the epoch
// fell within the few microseconds of the two clocks' reading gap of a half-period point (the wall and
// JACK's clock are read back to back: an error of a few us against a period of 5.3 ms at 256 frames).
// Why a wall time and not a JACK frame number: a frame number belongs to one server, while netjack2's
// slaves each count their own frames; the wall clock is what every node already shares for timetags.

#include <atomic>
#include <cstdint>

namespace ameoto {

class StartGate {
public:
    explicit StartGate(std::int64_t start_unix_ns = 0)
        : start_ns_(start_unix_ns), open_(start_unix_ns == 0), opened_(start_unix_ns == 0) {}

    bool open(std::int64_t cycle_unix_ns, std::int64_t period_ns) {
        if (open_) return true;
        if (cycle_unix_ns + period_ns / 2 < start_ns_) return false;
        open_ = true;
        lag_ns_.store(cycle_unix_ns - start_ns_, std::memory_order_relaxed);
        opened_.store(true, std::memory_order_release);
        return true;
    }

    std::int64_t start_unix_ns() const { return start_ns_; }
    bool opened() const { return opened_.load(std::memory_order_acquire); }
    // How long after the epoch the first cycle played (negative: up to half a period before).
    std::int64_t lag_ns() const { return lag_ns_.load(std::memory_order_relaxed); }

private:
    std::int64_t start_ns_;
    bool open_;
    std::atomic<bool> opened_;
    std::atomic<std::int64_t> lag_ns_{0};
};

}  // namespace ameoto
