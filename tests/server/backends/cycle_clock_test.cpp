// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/cycle_clock.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "server/realtime/wall_offset.hpp"

using ameoto::BlockTime;
using ameoto::CycleClock;
using ameoto::CycleReading;

namespace {

// A driver whose frames follow its crystal on a straight line (frame F at F / rate), and a callback
// that runs after it with a latency that is never negative: a floor that wanders by 10 us (a VM's timer
// slack), an exponential tail (mean 30 us), 2 % of wake-ups late by 0.5-5 ms, and optionally one
// stretch of 0.4 s in which every wake-up is 300 us late (another job's burst). The figures are those a
// probe logged on JACK's dummy driver on this 2-core machine (2026-12-02): median 64 us after the
// cycle, 99th percentile 11 ms while builds ran, half-second minima within +/- 15 us.
struct LoadedDriver {
    double ppm = 0.0;
    bool burst = false;
    std::uint32_t frames = 256;
    std::mt19937_64 rng{7};
    std::uint64_t frame = 0;
    std::int64_t start_ns = 5'000'000'000;   // the monotonic clock when frame 0 played
    std::int64_t lost_ns = 0;                 // time lost at xruns: the grid restarts later

    double seconds() const { return static_cast<double>(frame) / (48000.0 * (1.0 + ppm * 1e-6)); }
    std::int64_t frame_ns() const { return start_ns + lost_ns + static_cast<std::int64_t>(std::llround(seconds() * 1e9)); }
    double latency_ns() {
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        const double t = seconds();
        double l = 20'000.0 + 10'000.0 * (0.5 + 0.5 * std::sin(t * 0.9)) + std::exponential_distribution<double>(1.0 / 30'000.0)(rng);
        if (unit(rng) < 0.02) l += 500'000.0 + 4'500'000.0 * unit(rng);
        if (burst && t > 6.1 && t < 6.5) l += 300'000.0;
        return l;
    }
    CycleReading next(std::int64_t wall_minus_mono = 1'700'000'000'000'000'000) {
        CycleReading r;
        r.frames = frames;
        r.jack_frame = static_cast<std::uint32_t>(frame);
        r.period_usecs = static_cast<float>(frames / (48000.0 * (1.0 + ppm * 1e-6)) * 1e6);
        r.callback_mono_ns = frame_ns() + static_cast<std::int64_t>(latency_ns());
        r.wall_minus_mono_ns = wall_minus_mono;
        frame += frames;
        return r;
    }
};

// JACK's own delay-locked loop (jackd2 1.9.21, JackFrameTimer::IncFrameTimeAux, bandwidth 0.125 Hz),
// fed the same wake-ups, for the figure it is compared with: its estimate of each cycle's start.
struct JackLoop {
    bool started = false;
    double next = 0.0, period = 0.0, omega = 0.0, current = 0.0;
    double cycle(double callback_us, double period_us) {
        if (!started) {
            started = true;
            next = callback_us + period_us;
            period = period_us;
            omega = static_cast<float>(period_us * 7.854e-7);
            current = callback_us;
            return current;
        }
        const double delta = (callback_us - next) * omega;
        current = next;
        period += omega * delta;
        next += std::floor(period + 1.41 * delta + 0.5);
        return current;
    }
};

struct Spread {
    double lo = 1e18, hi = -1e18;
    void add(double v) { lo = std::min(lo, v); hi = std::max(hi, v); }
    double width() const { return hi - lo; }
};

}  // namespace

TEST_CASE("cycle clock: on a loaded machine each block's time lies on the driver's line to well under a sample (+/- 5 us)") {
    for (const double ppm : {0.0, 80.0}) {
        CAPTURE(ppm);
        LoadedDriver driver;
        driver.ppm = ppm;
        driver.burst = true;
        CycleClock clock(48000.0);
        JackLoop jack;
        Spread ours, theirs;
        std::int64_t last = 0;
        while (driver.seconds() < 14.0) {
            const double t = driver.seconds();
            const std::int64_t truth = driver.frame_ns() + 1'700'000'000'000'000'000;
            const CycleReading r = driver.next();
            const BlockTime b = clock.block(r);
            const double jack_us = jack.cycle(static_cast<double>(r.callback_mono_ns) * 1e-3, r.period_usecs);
            REQUIRE(b.valid);
            CHECK(b.unix_ns > last);   // monotonic, spikes and all
            last = b.unix_ns;
            if (t > 2.0) {   // locked: the line's slope is its own (the grid test waits 2.5 s for it)
                ours.add(static_cast<double>(b.unix_ns - truth));
                theirs.add(jack_us * 1e3 + 1'700'000'000'000'000'000.0 - static_cast<double>(truth));
            }
        }
        MESSAGE(ppm << " ppm: block times against the driver's line from 2 s to 14 s span " << ours.width() * 1e-3
                    << " us (JACK's loop fed the same wake-ups: " << theirs.width() * 1e-3 << " us); 20.8 us is a sample");
        // The bound: a spread under one sample (20.8 us) lets two drops' landings differ from their
        // distance by one sample at most (the issue-22 grid test's +/- 1). The floor's own 10 us wander
        // cannot be told from the driver's line and is followed; 5 us more is the 2 s mean's lag and
        // noise (measured 11-13 us).
        CHECK(ours.width() < 15'000.0);
        // The whole line sits above the true frame times by the floor of the latency only (20-30 us).
        CHECK(ours.lo > 15'000.0);
        CHECK(ours.hi < 40'000.0);
        CHECK(clock.full_buckets() == 56);
    }
}

// JACK's dummy driver (jackd2's JackTimedDriver) wakes on an absolute grid (its anchor + cycle x period,
// in double precision), so its frames keep the nominal rate exactly; the callback runs after the wake-up
// with the latency a probe logged on this 2-core VM (2026-12-06, 11 traces of 18 s, idle and loaded): a
// floor of about 30 us, from which a few wake-ups in a thousand come sooner (down to 0: the virtual CPU was
// already awake), an exponential tail and 2 % of wake-ups late by 0.5-5 ms.
struct GridDriver {
    std::mt19937_64 rng;
    std::uint64_t frame = 0;
    explicit GridDriver(unsigned seed) : rng(seed) {}
    std::int64_t frame_ns() const { return 5'000'000'000 + static_cast<std::int64_t>(std::llround(static_cast<double>(frame) / 48000.0 * 1e9)); }
    CycleReading next() {
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        double l = 30'000.0 + std::normal_distribution<double>(0.0, 2'000.0)(rng) + std::exponential_distribution<double>(1.0 / 15'000.0)(rng);
        const double p = unit(rng);
        if (p < 0.003) l = 30'000.0 * unit(rng);
        else if (p > 0.98) l += 500'000.0 + 4'500'000.0 * unit(rng);
        CycleReading r;
        r.frames = 256;
        r.jack_frame = static_cast<std::uint32_t>(frame);
        r.period_usecs = static_cast<float>(256 / 48000.0 * 1e6 * (1.0 + 40e-6));   // JACK's loop runs 40 ppm slow on it
        r.callback_mono_ns = frame_ns() + static_cast<std::int64_t>(std::max(l, 0.0));
        frame += 256;
        return r;
    }
};

TEST_CASE("cycle clock: a block 3 s after the start and the blocks of the next 10 s agree on the driver's grid to well under a sample") {
    // The grid test's measure (tests/integration/clock_test.cpp): 20 drops every 0.5 s from 3 s after the
    // client started, each one's landing relative to the first. Here: the block time's error against the
    // grid at each of those moments, less the first's, the largest of each take, over 40 seeded takes.
    // With the line through half-second minima (before 2026-12-06) the mean was 9.1 us and the largest
    // 24.7 us (over a sample at 48 kHz, 20.8 us); through quarter-second minima, 4.8 and 13.0 us.
    double sum = 0.0, worst = 0.0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        GridDriver driver(seed);
        CycleClock clock(48000.0);
        const double first = 3.0 + 0.0123 * seed;   // the first drop at another phase of the blocks each take
        double e0 = 0.0, take_worst = 0.0;
        for (int k = 0; k < 20;) {
            const double t = static_cast<double>(driver.frame) / 48000.0;
            const std::int64_t truth = driver.frame_ns();
            const BlockTime b = clock.block(driver.next());
            if (t < first + 0.5 * k) continue;
            const double e = static_cast<double>(b.unix_ns - truth);
            if (k == 0) e0 = e;
            take_worst = std::max(take_worst, std::fabs(e - e0));
            ++k;
        }
        sum += take_worst;
        worst = std::max(worst, take_worst);
    }
    MESSAGE("largest error relative to the block at 3 s, over 10 s: mean of 40 takes " << sum / 40.0 * 1e-3 << " us, largest " << worst * 1e-3 << " us");
    CHECK(sum / 40.0 < 6'500.0);
    CHECK(worst < 17'000.0);
}

TEST_CASE("cycle clock: time lost at an xrun restarts the envelope; so does a jump in JACK's frames, or time lost unreported") {
    for (const int how : {0, 1, 2}) {
        CAPTURE(how);   // 0: the xrun is reported; 1: JACK's frame counter jumps; 2: neither (found by the readings)
        LoadedDriver driver;
        CycleClock clock(48000.0);
        while (driver.seconds() < 5.0) clock.block(driver.next());
        REQUIRE(clock.full_buckets() == 20);
        driver.lost_ns += 2'400'000;   // the grid restarts 2.4 ms late
        if (how == 1) driver.frame += 512;
        CycleReading r = driver.next();
        r.xrun = how == 0;
        clock.block(r);
        if (how == 2) {   // found after a quarter second of late readings in a row
            CHECK(clock.full_buckets() == 20);
            while (driver.seconds() < 5.3) clock.block(driver.next());
        }
        CHECK(clock.full_buckets() == 0);
        Spread after;
        while (driver.seconds() < 8.0) {
            const double t = driver.seconds();
            const std::int64_t truth = driver.frame_ns() + 1'700'000'000'000'000'000;
            const BlockTime b = clock.block(driver.next());
            if (t > 5.6) after.add(static_cast<double>(b.unix_ns - truth));
        }
        MESSAGE("after the lost time (" << how << "): " << after.lo * 1e-3 << " to " << after.hi * 1e-3 << " us above the line");
        CHECK(after.lo > 15'000.0);
        CHECK(after.hi < 40'000.0);
    }
}

TEST_CASE("cycle clock: the wall clock's step moves the block time at once; the envelope lives on the monotonic clock") {
    LoadedDriver driver;
    CycleClock clock(48000.0);
    BlockTime before;
    while (driver.seconds() < 3.0) before = clock.block(driver.next());
    const BlockTime stepped = clock.block(driver.next(1'700'000'001'000'000'000));   // NTP stepped the wall 1 s on
    const double period_ns = 256 / 48000.0 * 1e9;
    CHECK(std::fabs(static_cast<double>(stepped.unix_ns - before.unix_ns) - 1e9 - period_ns) < 10'000.0);
    CHECK(clock.full_buckets() == 12);   // not restarted
}

TEST_CASE("cycle clock: a card 50 ppm fast is followed to its ppm, averaged; a loop not locked yet is ignored") {
    CycleClock clock(48000.0);
    const float period = static_cast<float>(256 / (48000.0 * (1.0 + 50e-6)) * 1e6);   // 50 ppm fast: shorter periods
    BlockTime t;
    CycleReading r;
    r.frames = 256;
    r.period_usecs = period;
    for (int k = 0; k < 48000 * 60 / 256; ++k) {   // a minute of cycles
        t = clock.block(r);
        r.jack_frame += 256;
        r.callback_mono_ns += static_cast<std::int64_t>(period * 1000.0f);
    }
    // Tolerance: the float period carries 24 bits (0.06 ppm of 5333 us) and the mean has settled (e^-6).
    CHECK((t.rate_ratio - 1.0) * 1e6 == doctest::Approx(50.0).epsilon(0.01));
    const double before = t.rate_ratio;
    r.period_usecs = 6000.0f;   // 11 % slow: a loop just after an xrun, not a card
    t = clock.block(r);
    CHECK(t.rate_ratio == before);
    clock.reset();
    CHECK(clock.ratio() == 1.0);
}

TEST_CASE("wall offset: monotonic + offset is the wall clock, to well under a sample") {
    const std::int64_t offset = ameoto::realtime_minus_monotonic_ns();
    const std::int64_t wall = ameoto::clock_ns(CLOCK_REALTIME);
    const std::int64_t from_monotonic = ameoto::clock_ns(CLOCK_MONOTONIC) + offset;
    // The two reads are a few hundred ns apart unless preempted; 20.8 us is one sample at 48 kHz.
    CHECK(std::llabs(from_monotonic - wall) < 20'000);
}
