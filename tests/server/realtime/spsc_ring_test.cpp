// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/realtime/spsc_ring.hpp"

#include <doctest/doctest.h>

#include <numeric>
#include <thread>
#include <vector>

using ameoto::SpscRing;

TEST_CASE("SpscRing writes all or nothing and reads back in order across the wrap") {
    SpscRing<int> ring(10);
    std::vector<int> a(6), out(10);
    std::iota(a.begin(), a.end(), 0);
    CHECK(ring.write(a.data(), 6));
    CHECK(ring.write_available() == 4);
    CHECK_FALSE(ring.write(a.data(), 5));   // no partial writes
    CHECK(ring.read(out.data(), 4) == 4);
    CHECK(out[3] == 3);
    CHECK(ring.write(a.data(), 6));         // wraps
    CHECK(ring.read(out.data(), 10) == 8);
    const std::vector<int> expected{4, 5, 0, 1, 2, 3, 4, 5};
    CHECK(std::vector<int>(out.begin(), out.begin() + 8) == expected);
    CHECK(ring.read(out.data(), 10) == 0);
}

TEST_CASE("SpscRing across two threads delivers every sample once") {
    constexpr int total = 1'000'000;
    SpscRing<int> ring(257);
    std::thread producer([&] {
        std::vector<int> block(37);
        for (int i = 0; i < total;) {
            const int n = std::min(37, total - i);
            std::iota(block.begin(), block.begin() + n, i);
            if (ring.write(block.data(), static_cast<std::size_t>(n))) i += n;
        }
    });
    std::vector<int> got(64);
    int expected = 0, failures = 0;
    while (expected < total) {
        const std::size_t n = ring.read(got.data(), got.size());
        for (std::size_t k = 0; k < n; ++k)
            if (got[k] != expected++) ++failures;
    }
    producer.join();
    CHECK(failures == 0);
}
