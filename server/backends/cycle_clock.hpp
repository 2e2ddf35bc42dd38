// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The JACK backend's block clock: the wall time at which each block's first frame plays, and the card's
// real rate against its nominal one, for AudioBridge::process (BlockTime).
//
// Interface (audio thread only; pure arithmetic on a fixed-size state, no system call, no allocation):
//   CycleClock clock(nominal_rate);
//   BlockTime t = clock.block({frames, jack_frame, period_usecs, callback_mono_ns, wall_minus_mono_ns, xrun});
//   clock.reset();   // a new JACK client (after the server came back): everything starts afresh
//
// How the block's time is found: the lower envelope of when the callback ran. A driver's frames follow
// its clock on a straight line (frame F plays at t0 + F / rate); the callback runs after the driver's
// wake-up and the graph before it, so each reading of the monotonic clock at the callback is that line
// plus a latency that is never negative: tens of microseconds usually, milliseconds when the machine is
// loaded. The earliest readings lie on the line. The readings, less the nominal F / rate, are kept as
// the minimum of each quarter second ("buckets", 64 of them: 16 s). The line is the least-squares line
// through those minima (the worst bucket left out once if it lies more than 20 us above the first fit),
// evaluated at this block's first frame.
//
// Why quarter seconds: what a timetag's sample depends on is the line's value at the newest block, and
// early on that is mostly the slope's error times half the span fitted; more minima in the same span
// make it smaller. Measured on JACK's dummy driver on this 2-core VM (2026-12-06; a probe logging each
// callback's CLOCK_MONOTONIC and JACK frame for 18 s, 11 traces, idle, beside two busy loops, beside a
// compiler; replayed offline through this class; the dummy driver wakes on an absolute grid, so the
// truth is the nominal rate): the half-second minima sit on a floor about 30 us above the lowest
// (scatter 5-12 us idle, 20 us in the worst trace) with a few buckets of a trace 10-35 us lower (wake-ups
// that found the virtual CPU awake), and in two traces the floor itself moved by 30-50 us for seconds
// under load. Measured as the grid test measures (tests/integration/clock_test.cpp: a block 3 s after
// the start against the blocks every 0.5 s over the next 9.5 s, the largest difference of each run, 176
// runs from 16 starts in each trace): half-second minima, median 11.5 us, 90th percentile 40 us, over a
// sample (20.8 us) in 45 runs; quarter-second minima, median 9.6 us, 90th percentile 27 us, over a sample
// in 26 runs. Eighth-second minima, the 2nd-5th lowest reading of each bucket instead of the lowest, a
// Theil-Sen (median) line and a two-sided outlier cut did no better (24-37 runs over). The line lying
// below every minimum as close as it can (the linear-programming estimator of Moon, Skelly and Towsley,
// 1999) did worst (75 of 112 over): it sits on the rare early wake-ups, and drops by their depth when one
// comes. What is left is the floor's own wander, which no fit can tell from the driver's line: with the
// true slope given, 10 of the 176 runs were still over a sample. A longer wait than 3 s did not help
// (over a sample in 14-17 % of runs from 3 s to 6 s). In the grid test itself (ameotod's own readings
// logged in 6 takes without xruns, 2026-12-06) that wander is larger: the floor stepped by 30-60 us for
// seconds at a time, at any moment of the take (one step came 12.7 s after the start), and the block
// times followed it with either bucket length (largest difference from the first drop's block 15-57 us
// with quarter seconds, 21-62 us with half seconds); takes with such a step land drops 2-3 samples off.
//
// Why not JACK's own filtered cycle times (jack_get_cycle_times' current_usecs), as before: JACK's
// delay-locked loop (bandwidth 0.125 Hz) averages the latencies rather than ignoring them, so on a
// loaded machine it wanders. Measured on JACK's dummy driver, 2 cores, 256 frames (2026-12-02, a probe
// logging both each cycle): after the first 4 s its estimate moved by 30 us in 8 s and then by 150 us in
// 1 s when the builds of other jobs started, with no xrun, while the half-second minima of the
// callback's readings stayed within +/- 15 us; and for the first 3 s after jackd starts its loop is
// still settling (83 us off at start). 20.8 us is one sample at 48 kHz: the issue-22 grid test saw
// drops land 1 and 2 samples off through JACK's loop.
//
// Time lost: an xrun re-anchors a timed driver (JACK's dummy driver restarts its grid from the late
// wake-up), so the line moves later. The envelope restarts when the backend saw an xrun, when JACK's
// frame counter does not continue from the last block, and when a quarter second of readings in a row
// all lie more than 1 ms above the line (time lost that no xrun reported). Until eight buckets are full
// (2 s), the line's slope is the one before the restart, or at a start JACK's period (its loop's rate,
// averaged): a client's clock is locked 2 s after it starts (JACK's loop, itself just started, can be
// 30 ppm off: 60 us over those 2 s; on the dummy driver, whose rate is exactly nominal, it read -25 to
// -45 ppm throughout the 2026-12-06 traces).
//
// The rate ratio (for /status's ppm and the bridge's extrapolation within a block) is frames / (period
// x nominal rate) from JACK's loop, averaged exponentially over about 10 s: JACK's loop already smooths
// the period, and a sound card's crystal drifts with temperature over minutes, so a 10 s mean is steady
// and still follows it. A ratio outside 1 +/- 1 % (a loop that has not locked yet) is ignored.
//
// The wall time is the monotonic time plus wall_minus_mono_ns (realtime_minus_monotonic_ns(), read
// every block), so an NTP step of the wall clock moves block times at once and does not disturb the
// envelope, which lives on the monotonic clock.

#include <cstdint>

#include "server/realtime/audio_bridge.hpp"

namespace ameoto {

struct CycleReading {
    std::uint32_t frames = 0;             // this block's length
    std::uint32_t jack_frame = 0;         // JACK's frame counter at the block's first frame (wraps at 2^32)
    float period_usecs = 0.0f;            // JACK's filtered period (0: unknown)
    std::int64_t callback_mono_ns = 0;    // CLOCK_MONOTONIC read when the callback began
    std::int64_t wall_minus_mono_ns = 0;  // CLOCK_REALTIME - CLOCK_MONOTONIC now
    bool xrun = false;                    // the backend saw an xrun since the last block
};

class CycleClock {
public:
    explicit CycleClock(double nominal_rate);

    void reset();
    BlockTime block(const CycleReading& r);

    double ratio() const { return ratio_; }
    int full_buckets() const { return full_; }   // for tests: how much of the window holds readings

private:
    struct Bucket {
        double x = 0.0;   // frames since the anchor at the minimum
        double r = 0.0;   // reading - anchor - x / nominal rate, ns, at the minimum
    };
    static constexpr int kBuckets = 64;        // 16 s for the slope
    static constexpr int kSlopeBuckets = 8;    // at least 2 s before the slope is the envelope's own
    static constexpr double kBucketSeconds = 0.25;
    static constexpr double kLostSeconds = 0.25;   // every reading this long far above the line: time lost
    static constexpr double kOutlierNs = 20'000.0;
    static constexpr double kLostNs = 1'000'000.0;
    static constexpr double kAveragingSeconds = 10.0;

    void restart_envelope(const CycleReading& r);
    void update_ratio(const CycleReading& r);
    double line_at(double x);   // the envelope's line at frame x (ns after the anchor, less x / rate)
    double fit_slope(int skip, double& mx, double& mr) const;
    void fit_line(double& mx, double& mr, double& slope) const;

    double nominal_rate_;
    double ns_per_frame_;
    double ratio_ = 1.0;
    bool ratio_started_ = false;

    bool started_ = false;
    double slope_ = 0.0;           // the envelope's last own slope, kept across a restart
    bool has_slope_ = false;
    std::uint32_t next_jack_frame_ = 0;
    std::int64_t anchor_ns_ = 0;   // monotonic reading of the envelope's first block
    std::int64_t x_ = 0;           // frames from the anchor to this block's first frame
    Bucket ring_[kBuckets];
    int full_ = 0;                 // full buckets in ring_ (the newest at head_ - 1)
    int head_ = 0;
    struct Line {
        double mx = 0.0, mr = 0.0;   // the centroid of the buckets fitted
        double slope = 0.0;          // ns per frame beyond the nominal
    };
    Line fit_;                     // fit_line()'s result for ring_ as it is
    bool fit_valid_ = false;
    Bucket current_;               // the bucket being filled
    bool current_has_ = false;
    std::int64_t current_end_x_ = 0;
    std::int64_t high_since_x_ = -1;   // the first of the readings in a row more than kLostNs above the line (-1: none)
};

}  // namespace ameoto
