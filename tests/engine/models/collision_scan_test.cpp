// SPDX-License-Identifier: GPL-3.0-or-later
// The collision scan (engine/models/collision_scan.hpp): the AVX2 and scalar passes list the same
// masses and count the same band as collide()'s per-mass tests, written out here.
#include "engine/models/collision_scan.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using ameoto::CollisionScanBounds;
using ameoto::scan_for_collisions;

struct Scan {
    std::vector<int> listed;
    int near = 0;
};

// collide()'s tests as it wrote them before the scan (drop_on_canopy_collide.cpp).
Scan reference(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
               const CollisionScanBounds& b) {
    Scan s;
    for (std::size_t m = 0; m < x.size(); ++m) {
        if (z[m] > b.high) continue;
        if (x[m] * x[m] + y[m] * y[m] > b.r2_max) continue;
        if (z[m] <= b.band_top && z[m] >= b.band_below) ++s.near;
        if (z[m] > b.limit) continue;
        if (z[m] > b.limit_u) continue;
        s.listed.push_back(static_cast<int>(m));
    }
    return s;
}

Scan scan(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
          const CollisionScanBounds& b, bool portable) {
    ameoto::set_portable_collision_scan(portable);
    Scan s;
    s.listed.assign(x.size(), -1);
    s.near = 3;   // adds to what is there
    const int n = scan_for_collisions(x.data(), y.data(), z.data(), static_cast<int>(x.size()), b, s.listed.data(), s.near);
    ameoto::set_portable_collision_scan(false);
    s.listed.resize(static_cast<std::size_t>(n));
    s.near -= 3;
    return s;
}

}  // namespace

TEST_CASE("collision_scan: AVX2 and scalar passes list what collide()'s per-mass tests pass, NaN included") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> plan(-0.6, 0.6), height(-0.15, 0.15);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    int listed_total = 0, near_total = 0, trials = 0;
    for (int n : {0, 1, 3, 4, 5, 7, 8, 122, 123, 125}) {
        for (int trial = 0; trial < 40; ++trial) {
            std::vector<double> x(static_cast<std::size_t>(n)), y(x.size()), z(x.size());
            for (int m = 0; m < n; ++m) {
                x[static_cast<std::size_t>(m)] = plan(rng);
                y[static_cast<std::size_t>(m)] = plan(rng);
                z[static_cast<std::size_t>(m)] = height(rng);
                if (rng() % 17 == 0) (rng() % 2 ? z : x)[static_cast<std::size_t>(m)] = nan;
            }
            CollisionScanBounds b;
            b.r2_max = 0.25 * (1.0 + 1e-12);
            b.band_below = -0.1;
            b.band_top = 0.05;
            b.limit = trial % 3 == 0 ? 0.05 : 0.01 * (trial % 5);
            b.high = std::max(b.limit, b.band_top);
            b.limit_u = trial % 2 ? std::numeric_limits<double>::infinity() : 0.004 * (trial % 7) - 0.01;
            if (trial == 39) b.limit_u = nan;   // a bound that is NaN passes every mass, as a > NaN does
            const Scan want = reference(x, y, z, b);
            const Scan fast = scan(x, y, z, b, false);
            const Scan slow = scan(x, y, z, b, true);
            CHECK(fast.listed == want.listed);
            CHECK(slow.listed == want.listed);
            CHECK(fast.near == want.near);
            CHECK(slow.near == want.near);
            listed_total += static_cast<int>(want.listed.size());
            near_total += want.near;
            ++trials;
        }
    }
    // The cases exercise both outcomes.
    CHECK(listed_total > 100);
    CHECK(near_total > 100);
    CHECK(trials == 400);
}
