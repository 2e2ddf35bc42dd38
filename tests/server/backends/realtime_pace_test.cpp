// SPDX-License-Identifier: GPL-3.0-or-later
// server/backends/realtime_pace.hpp: the null backend's period boundaries. On time, every block
// waits for start + k * period (no drift over a day of blocks); a late block counts one xrun and
// the next waits for the first boundary after it, so the render thread sleeps after every block
// even when it cannot keep up (it runs at SCHED_FIFO when it may; see the header for why).

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>
#include <cstdint>
#include <random>

#include "server/backends/realtime_pace.hpp"

namespace {
constexpr double period_s = 256.0 / 48000.0;   // 5 333 333.3 ns
constexpr double period_ns = period_s * 1e9;
constexpr std::int64_t start = 1'000'000'000;

std::int64_t boundary(std::uint64_t k) { return start + static_cast<std::int64_t>(std::llround(static_cast<double>(k) * period_ns)); }
}  // namespace

TEST_CASE("on time, each block waits for its own period boundary, with no drift over a day") {
    ameoto::RealtimePace pace(period_s, start);
    // Blocks that take a tenth of a period.
    for (std::uint64_t k = 1; k <= 1000; ++k) {
        const auto next = pace.after_block(boundary(k - 1) + static_cast<std::int64_t>(period_ns / 10));
        CHECK_FALSE(next.late);
        CHECK(next.wake_ns == boundary(k));
    }
    // A day of 256-frame blocks at 48 kHz (16.2 million) in one go: the boundary is k periods from
    // the start to the nanosecond, where summing a period rounded to 5 333 333 ns would lag 5.4 ms.
    ameoto::RealtimePace day(period_s, start);
    const std::uint64_t blocks = 86400ull * 48000 / 256;
    ameoto::RealtimePace::Next next;
    for (std::uint64_t k = 1; k <= blocks; ++k) next = day.after_block(boundary(k - 1));
    CHECK_FALSE(next.late);
    CHECK(next.wake_ns - start == 86'400'000'000'000);
}

TEST_CASE("a block that finishes exactly on its boundary is on time") {
    ameoto::RealtimePace pace(period_s, start);
    const auto next = pace.after_block(boundary(1));
    CHECK_FALSE(next.late);
    CHECK(next.wake_ns == boundary(1));
}

TEST_CASE("a late block counts one xrun and the next waits for the first boundary after it") {
    ameoto::RealtimePace pace(period_s, start);
    // Block 0 finishes 1.3 periods in: it missed boundary 1; the next starts at boundary 2.
    auto next = pace.after_block(start + static_cast<std::int64_t>(1.3 * period_ns));
    CHECK(next.late);
    CHECK(next.wake_ns == boundary(2));
    // That block is on time against boundary 3 ...
    next = pace.after_block(boundary(2) + 1000);
    CHECK_FALSE(next.late);
    CHECK(next.wake_ns == boundary(3));
    // ... and one that misses four boundaries at once is still one xrun, and waits for the fifth.
    next = pace.after_block(boundary(7) + 10);
    CHECK(next.late);
    CHECK(next.wake_ns == boundary(8));
    // Late by one nanosecond past a boundary: waits for the next, never for the one just passed.
    next = pace.after_block(boundary(9) + 1);
    CHECK(next.late);
    CHECK(next.wake_ns == boundary(10));
}

TEST_CASE("a renderer slower than real time still leaves the CPU idle between blocks") {
    // Every block takes 1.3 periods: the old pace (start the next block at once when late) kept the
    // thread busy 100 % of the time; on the grid it works 1.3 of every 2 periods.
    ameoto::RealtimePace pace(period_s, start);
    std::int64_t now = start, busy = 0;
    int late = 0;
    constexpr int blocks = 1000;
    for (int b = 0; b < blocks; ++b) {
        const auto work = static_cast<std::int64_t>(1.3 * period_ns);
        now += work;
        busy += work;
        const auto next = pace.after_block(now);
        late += next.late ? 1 : 0;
        REQUIRE(next.wake_ns > now);
        now = next.wake_ns;
    }
    CHECK(late == blocks);
    CHECK(static_cast<double>(busy) / static_cast<double>(now - start) == ameoto::test::relative(1.3 / 2.0).epsilon(1e-3));
}

TEST_CASE("fuzz: whatever the blocks take, the wake is the first boundary not before the finish, a period or less away") {
    std::mt19937_64 random(20261122);
    std::uniform_real_distribution<double> work_periods(0.0, 3.5);
    for (int run = 0; run < 20; ++run) {
        ameoto::RealtimePace pace(period_s, start);
        std::int64_t now = start, due = boundary(1);
        long late = 0, counted = 0;
        for (int b = 0; b < 5000; ++b) {
            now += static_cast<std::int64_t>(work_periods(random) * period_ns);
            const auto next = pace.after_block(now);
            const bool expect_late = now > due;
            CHECK(next.late == expect_late);
            late += next.late ? 1 : 0;
            counted += expect_late ? 1 : 0;
            CHECK(next.wake_ns >= now);
            CHECK(next.wake_ns - now <= static_cast<std::int64_t>(period_ns) + 1);
            // On the grid: a whole number of periods from the start, to the nanosecond of rounding.
            const double periods = static_cast<double>(next.wake_ns - start) / period_ns;
            CHECK(std::abs(periods - std::round(periods)) * period_ns <= 1.0);
            if (next.late) CHECK(next.wake_ns > now);
            now = next.wake_ns;
            due = boundary(static_cast<std::uint64_t>(std::llround(periods)) + 1);
        }
        CHECK(late == counted);
    }
}
