// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/cycle_clock.hpp"

#include <doctest/doctest.h>

#include "server/realtime/wall_offset.hpp"

using ameoto::BlockTime;
using ameoto::CycleClock;

TEST_CASE("cycle clock: the cycle's wall time is the filtered time, moved by the gap between two readings of JACK's clock") {
    CycleClock clock(48000.0);
    // JACK says the cycle began at 1 000 000 us; its clock reads 1 000 250 us when the wall reads T.
    const std::int64_t wall = 1'700'000'000'000'000'000;
    const BlockTime t = clock.block(256, 1'000'000, 256 / 48000.0 * 1e6, 1'000'250, wall);
    CHECK(t.valid);
    CHECK(t.unix_ns == wall - 250'000);
    CHECK(t.rate_ratio == doctest::Approx(1.0).epsilon(1e-7));   // JACK hands the period as a float: 24 bits
}

TEST_CASE("cycle clock: a card 50 ppm fast is followed to its ppm, averaged; a loop not locked yet is ignored") {
    CycleClock clock(48000.0);
    const float period = static_cast<float>(256 / (48000.0 * (1.0 + 50e-6)) * 1e6);   // 50 ppm fast: shorter periods
    BlockTime t;
    for (int k = 0; k < 48000 * 60 / 256; ++k) t = clock.block(256, 0, period, 0, 0);   // a minute of cycles
    // Tolerance: the float period carries 24 bits (0.06 ppm of 5333 us) and the mean has settled (e^-6).
    CHECK((t.rate_ratio - 1.0) * 1e6 == doctest::Approx(50.0).epsilon(0.01));
    const double before = t.rate_ratio;
    t = clock.block(256, 0, 6000.0f, 0, 0);   // 11 % slow: a loop just after an xrun, not a card
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
