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
// the minimum of each half second ("buckets", 32 of them: 16 s). The line is the least-squares line
// through those minima (the worst bucket left out once if it lies more than 20 us above the first fit),
// evaluated at this block's first frame. Measured on JACK's dummy driver here (2026-12-02), the
// half-second minima scatter over 40 us (the VM's timer): the lowest of 2 s of them moved by 15-20 us
// at bucket boundaries, the least-squares line over 16 s moves by about a microsecond a bucket.
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
// frame counter does not continue from the last block, and when half a bucket of readings all lie more
// than 1 ms above the line (time lost that no xrun reported). Until four buckets are full (2 s), the
// line's slope is the one before the restart, or at a start JACK's period (its loop's rate, averaged):
// a client's clock is locked 2 s after it starts (JACK's loop, itself just started, can be 30 ppm off:
// 60 us over those 2 s).
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
    static constexpr int kBuckets = 32;        // 16 s for the slope
    static constexpr int kSlopeBuckets = 4;    // at least 2 s before the slope is the envelope's own
    static constexpr double kBucketSeconds = 0.5;
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
    int current_count_ = 0;
    int current_high_ = 0;         // readings of the current bucket more than kLostNs above the line
};

}  // namespace ameoto
