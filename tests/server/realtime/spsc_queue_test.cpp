// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/realtime/spsc_queue.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <thread>

using ameoto::SpscQueue;

TEST_CASE("SpscQueue holds exactly its capacity, in order") {
    SpscQueue<int> q(3);
    CHECK(q.capacity() == 3);
    int v = -1;
    CHECK_FALSE(q.try_pop(v));
    CHECK(q.try_push(1));
    CHECK(q.try_push(2));
    CHECK(q.try_push(3));
    CHECK_FALSE(q.try_push(4));   // full at exactly capacity
    CHECK(q.size_approx() == 3);
    CHECK(q.try_pop(v));
    CHECK(v == 1);
    CHECK(q.try_push(4));         // one slot freed, one accepted
    CHECK_FALSE(q.try_push(5));
    for (int expected : {2, 3, 4}) {
        REQUIRE(q.try_pop(v));
        CHECK(v == expected);
    }
    CHECK_FALSE(q.try_pop(v));
    CHECK(q.size_approx() == 0);
}

TEST_CASE("SpscQueue wraps around many times without losing or duplicating") {
    SpscQueue<std::uint64_t> q(7);
    std::uint64_t next_in = 0, next_out = 0, v = 0;
    std::mt19937 rng(1);
    for (int step = 0; step < 100000; ++step) {
        if (rng() % 2) {
            if (q.try_push(next_in)) ++next_in;
        } else if (q.try_pop(v)) {
            REQUIRE(v == next_out);
            ++next_out;
        }
        REQUIRE(next_in - next_out <= 7);
    }
    CHECK(next_out > 1000);
}

TEST_CASE("SpscQueue across two threads: every value arrives once, in order (fuzzed timing)") {
    // Count and order check under real concurrency: the producer pushes 0..N-1 with random pauses,
    // the consumer pops with other random pauses; any lost, duplicated or torn value fails.
    struct Item {
        std::uint64_t value;
        std::uint64_t check;   // ~value: a torn copy breaks the pair
    };
    constexpr std::uint64_t total = 2'000'000;
    SpscQueue<Item> q(64);
    std::thread producer([&] {
        std::minstd_rand rng(7);
        for (std::uint64_t i = 0; i < total;) {
            if (q.try_push({i, ~i})) ++i;
            if (rng() % 64 == 0) std::this_thread::yield();
        }
    });
    std::minstd_rand rng(11);
    std::uint64_t expected = 0, failures = 0;
    Item item{};
    while (expected < total) {
        if (q.try_pop(item)) {
            if (item.value != expected || item.check != ~expected) ++failures;
            ++expected;
        }
        if (rng() % 64 == 0) std::this_thread::yield();
    }
    producer.join();
    CHECK(failures == 0);
    CHECK_FALSE(q.try_pop(item));
}
