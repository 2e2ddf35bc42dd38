// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The wall clock (CLOCK_REALTIME, what OSC timetags count) minus the monotonic clock (what the null
// backend's period grid and JACK's cycle times count), read without a system call (both are vDSO reads
// on Linux), so the audio thread may call it.
//
// Interface (any thread, the audio thread included):
//   std::int64_t offset = realtime_minus_monotonic_ns();   // add to a CLOCK_MONOTONIC time -> unix ns
//
// Why three tries: a read of one clock between two reads of the other brackets the instant; the
// tightest bracket (the one not preempted or interrupted) is kept, so the offset is good to well under
// a microsecond (a sample at 48 kHz is 20.8 us). The offset moves only when NTP slews or steps the wall
// clock; it is read again for every block, so a step is followed within one block.

#include <time.h>

#include <cstdint>

namespace ameoto {

inline std::int64_t clock_ns(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return static_cast<std::int64_t>(t.tv_sec) * 1000000000 + t.tv_nsec;
}

inline std::int64_t realtime_minus_monotonic_ns() {
    std::int64_t best_offset = 0, best_span = INT64_MAX;
    for (int attempt = 0; attempt < 3; ++attempt) {
        const std::int64_t before = clock_ns(CLOCK_MONOTONIC);
        const std::int64_t wall = clock_ns(CLOCK_REALTIME);
        const std::int64_t after = clock_ns(CLOCK_MONOTONIC);
        if (after - before < best_span) {
            best_span = after - before;
            best_offset = wall - (before + (after - before) / 2);
        }
    }
    return best_offset;
}

}  // namespace ameoto
