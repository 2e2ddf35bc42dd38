// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/air_canopy_kernels and engine/core/lane_sums: the in-air canopy's baseline and
// AVX2 loops give the same bits, and the eight-sum reductions are the sums they claim to be.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "engine/core/cpu_features.hpp"
#include "engine/core/lane_sums.hpp"
#include "engine/core/random.hpp"
#include "engine/models/air_canopy_kernels.hpp"

namespace ameoto {

namespace {

std::vector<double> noise(Random& r, std::size_t n, double scale) {
    std::vector<double> v(n);
    for (double& x : v) x = scale * r.uniform(-1.0, 1.0);
    return v;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("lane sums: dot, dot2 and abs_dot are the sums of their terms, for every length's tail") {
    Random r(7);
    for (std::size_t n : {0u, 1u, 7u, 8u, 9u, 15u, 16u, 17u, 399u, 400u, 403u}) {
        const auto a = noise(r, n, 1.0), x = noise(r, n, 3.0), b = noise(r, n, 0.5), y = noise(r, n, 2.0);
        long double dot = 0.0L, dot2 = 0.0L, abs_dot = 0.0L, size = 0.0L;
        for (std::size_t k = 0; k < n; ++k) {
            dot += static_cast<long double>(a[k]) * x[k];
            dot2 += static_cast<long double>(a[k]) * x[k] + static_cast<long double>(b[k]) * y[k];
            abs_dot += static_cast<long double>(a[k]) * std::fabs(x[k]);
            size += std::fabs(a[k] * x[k]) + std::fabs(b[k] * y[k]);
        }
        // Rounding only: n additions of terms whose magnitudes sum to `size`.
        const double tolerance = 1e-15 * static_cast<double>(n + 1) * static_cast<double>(size + 1.0L);
        CHECK(std::fabs(lane_sums::dot(a.data(), x.data(), n) - static_cast<double>(dot)) <= tolerance);
        CHECK(std::fabs(lane_sums::dot2(a.data(), x.data(), b.data(), y.data(), n) - static_cast<double>(dot2)) <= tolerance);
        CHECK(std::fabs(lane_sums::abs_dot(a.data(), x.data(), n) - static_cast<double>(abs_dot)) <= tolerance);
    }
    // The order is the header's: term k into running sum k mod 8, folded pairwise, then the tail.
    std::vector<double> one(9, 1.0), big = {1e16, 1.0, 1.0, 1.0, -1e16, 1.0, 1.0, 1.0, 1.0};
    // Sums 0 and 4 cancel exactly ((1e16 + -1e16) first), the rest are exact: 7.
    CHECK(lane_sums::dot(one.data(), big.data(), 9) == 7.0);
}

TEST_CASE("air canopy kernels: the AVX2 step and taps give the baseline's bits") {
    const AirKernels& base = air_kernels_baseline();
    const AirKernels& used = air_kernels();
    CHECK(used.avx2 == cpu_has_avx2());
    if (!used.avx2) MESSAGE("no AVX2 on this CPU: the baseline pair runs, compared with itself");
    Random r(11);
    for (std::size_t n : {1u, 5u, 8u, 13u, 400u}) {
        const auto t11 = noise(r, n, 1.0), t12 = noise(r, n, 2e-5), t21 = noise(r, n, 3e4), t22 = noise(r, n, 1.0);
        auto q1 = noise(r, n, 1e-6), qd1 = noise(r, n, 1e-3), p1 = noise(r, n, 10.0), a1 = noise(r, n, 1.0);
        auto q2 = q1, qd2 = qd1, p2 = p1, a2 = a1;
        const double t = 1.0 / 48000.0;
        for (int step = 0; step < 50; ++step) {
            if (step % 7 == 3)   // a force now and then (the step clears it)
                for (std::size_t k = 0; k < n; ++k) p1[k] = p2[k] = r.uniform(-5.0, 5.0);
            base.advance(n, q1.data(), qd1.data(), p1.data(), a1.data(), t11.data(), t12.data(), t21.data(), t22.data(), t, 1.0 / t);
            used.advance(n, q2.data(), qd2.data(), p2.data(), a2.data(), t11.data(), t12.data(), t21.data(), t22.data(), t, 1.0 / t);
        }
        bool same = true;
        for (std::size_t k = 0; k < n; ++k)
            same = same && same_bits(q1[k], q2[k]) && same_bits(qd1[k], qd2[k]) && same_bits(a1[k], a2[k]) && p2[k] == 0.0;
        CHECK(same);
        const auto a = noise(r, n, 1.0), x = noise(r, n, 3.0), b = noise(r, n, 0.5), y = noise(r, n, 2.0);
        CHECK(same_bits(base.taps(a.data(), x.data(), b.data(), y.data(), n), used.taps(a.data(), x.data(), b.data(), y.data(), n)));
        CHECK(same_bits(base.taps(a.data(), x.data(), b.data(), y.data(), n), lane_sums::dot2(a.data(), x.data(), b.data(), y.data(), n)));
    }
}

}  // namespace ameoto
