// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The null backend's real-time pace: when each block may start, on a fixed grid of periods counted
// from the first block, as a sound card's period interrupts fall.
//
// Interface:
//   RealtimePace pace(period_s, start_ns);        // start_ns: the monotonic clock at the first block
//   const RealtimePace::Next next = pace.after_block(now_ns);   // a block just finished at now_ns
//   next.late      // it finished after the period boundary it was due by: an xrun
//   next.wake_ns   // sleep until then (absolute, monotonic): never before now_ns, after it when late
//
// Why a grid: deadlines are start + k * period, computed from k rather than summed, so a day of
// blocks does not drift by the rounding of one period to whole nanoseconds.
// Why a late block waits for the next boundary instead of starting the next block at once: that is
// what a sound card does (the slot is gone; the next period begins at its next interrupt), and it is
// what keeps a render thread that cannot keep up from taking a CPU whole. The thread runs at
// SCHED_FIFO when it may (root, or an rtprio limit): starting each block at once, a renderer slower
// than real time (a scene too heavy for the machine, or the sanitized build in CI) never slept, and
// the kernel's real-time throttling left 5 % of that CPU to every other thread: the OSC thread that
// answers /status and /version, the client, the other programs. Waiting for the boundary, a block
// that takes c periods (1 < c) leaves the CPU idle for ceil(c) - c of them; every block sleeps.
// Cost: a late block costs its whole slot, so the audio clock falls behind the wall by whole
// periods, as with hardware; each late block counts one xrun however many boundaries it missed.

#include <cmath>
#include <cstdint>

namespace ameoto {

class RealtimePace {
public:
    struct Next {
        std::int64_t wake_ns = 0;
        bool late = false;
    };

    RealtimePace(double period_s, std::int64_t start_ns) : period_ns_(period_s * 1e9), start_ns_(start_ns) {}

    Next after_block(std::int64_t now_ns) {
        Next next;
        ++periods_;
        if (now_ns > boundary(periods_)) {
            // Missed: the next block waits for the first boundary after now.
            next.late = true;
            periods_ = static_cast<std::uint64_t>(std::floor(static_cast<double>(now_ns - start_ns_) / period_ns_)) + 1;
            while (boundary(periods_) <= now_ns) ++periods_;   // rounding at an exact boundary
        }
        next.wake_ns = boundary(periods_);
        return next;
    }

private:
    std::int64_t boundary(std::uint64_t k) const {
        return start_ns_ + static_cast<std::int64_t>(std::llround(static_cast<double>(k) * period_ns_));
    }

    double period_ns_;
    std::int64_t start_ns_;
    std::uint64_t periods_ = 0;   // the boundary the block in hand is due by
};

}  // namespace ameoto
