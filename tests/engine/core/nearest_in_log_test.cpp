// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/nearest_in_log.hpp: the nearest value in log x, either side of each geometric midpoint.
#include "engine/core/nearest_in_log.hpp"

#include <doctest/doctest.h>

#include <cmath>

using ameoto::nearest_in_log;

TEST_CASE("nearest in log: each value, either side of the geometric midpoints, and beyond the ends") {
    const double v[4] = {1.0, 4.0, 9.0, 100.0};   // midpoints 2, 6, 30
    CHECK(nearest_in_log(v, 4, 0.01) == 0);
    CHECK(nearest_in_log(v, 4, 1.99) == 0);
    CHECK(nearest_in_log(v, 4, 2.01) == 1);
    CHECK(nearest_in_log(v, 4, 5.99) == 1);
    CHECK(nearest_in_log(v, 4, 6.01) == 2);
    CHECK(nearest_in_log(v, 4, 29.9) == 2);
    CHECK(nearest_in_log(v, 4, 30.1) == 3);
    CHECK(nearest_in_log(v, 4, 1e9) == 3);
    for (int i = 0; i < 4; ++i) CHECK(nearest_in_log(v, 4, v[i]) == i);
    CHECK(nearest_in_log(v, 1, 50.0) == 0);
    CHECK(nearest_in_log(v, 0, 1.0) == -1);
    // Against the definition on a fine geometric grid (the impact templates': 5 % steps).
    double grid[51];
    for (int k = 0; k < 51; ++k) grid[k] = 0.5e-3 * std::pow(1.05, k);
    for (double x = 0.3e-3; x < 8e-3; x *= 1.0037) {
        int best = 0;
        for (int k = 1; k < 51; ++k)
            if (std::abs(std::log(x / grid[k])) < std::abs(std::log(x / grid[best]))) best = k;
        CHECK(nearest_in_log(grid, 51, x) == best);
    }
}
