// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The JACK backend's block clock: from JACK's delay-locked loop (jack_get_cycle_times: the time its
// filter assigns to the current cycle's first frame, and the filtered period), the wall time at which a
// block plays and the card's real rate against its nominal one, for AudioBridge::process (BlockTime).
//
// Interface (audio thread only; pure arithmetic, no system call):
//   CycleClock clock(nominal_rate);
//   BlockTime t = clock.block(frames, cycle_usecs, period_usecs, now_usecs, now_unix_ns);
//   clock.reset();   // a new JACK client (after the server came back): its loop starts afresh
//
// cycle_usecs and now_usecs are JACK's clock (jack_get_time's microseconds); now_unix_ns is the wall
// clock read next to now_usecs. The cycle's wall time is now_unix_ns - (now_usecs - cycle_usecs): only
// the difference of two readings of JACK's clock is used, so it does not matter which clock JACK counts.
// The rate ratio is frames / (period x nominal rate), averaged exponentially over about 10 s: JACK's
// loop already smooths the period over its bandwidth (about 1 Hz), and a sound card's crystal drifts
// with temperature over minutes, so a 10 s mean is steady (for /status) and still follows it. A ratio
// outside 1 +/- 1 % (a loop that has not locked yet, just after a start or an xrun) is ignored.

#include <cstdint>

#include "server/realtime/audio_bridge.hpp"

namespace ameoto {

class CycleClock {
public:
    explicit CycleClock(double nominal_rate) : nominal_rate_(nominal_rate) {}

    void reset() { started_ = false; ratio_ = 1.0; }

    BlockTime block(std::uint32_t frames, std::uint64_t cycle_usecs, float period_usecs, std::uint64_t now_usecs,
                    std::int64_t now_unix_ns) {
        BlockTime t;
        t.valid = true;
        const std::int64_t since_cycle_us = static_cast<std::int64_t>(now_usecs) - static_cast<std::int64_t>(cycle_usecs);
        t.unix_ns = now_unix_ns - since_cycle_us * 1000;
        if (period_usecs > 0.0f) {
            const double measured = static_cast<double>(frames) / (static_cast<double>(period_usecs) * 1e-6 * nominal_rate_);
            if (measured > 0.99 && measured < 1.01) {
                const double period_s = static_cast<double>(frames) / nominal_rate_;
                const double alpha = period_s / averaging_s > 1.0 ? 1.0 : period_s / averaging_s;
                ratio_ = started_ ? ratio_ + alpha * (measured - ratio_) : measured;
                started_ = true;
            }
        }
        t.rate_ratio = ratio_;
        return t;
    }

    double ratio() const { return ratio_; }

private:
    static constexpr double averaging_s = 10.0;
    double nominal_rate_;
    double ratio_ = 1.0;
    bool started_ = false;
};

}  // namespace ameoto
