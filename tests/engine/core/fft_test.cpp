// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/fft.hpp against the transform's definition.
#include "engine/core/fft.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/core/random.hpp"

using ameoto::fft_in_place;

namespace {

// X[k] = sum_j x[j] exp(-2 pi i j k / n), summed directly (O(n^2)).
std::vector<std::complex<double>> direct_dft(const std::vector<std::complex<double>>& x) {
    const std::size_t n = x.size();
    std::vector<std::complex<double>> out(n);
    for (std::size_t k = 0; k < n; ++k)
        for (std::size_t j = 0; j < n; ++j)
            out[k] += x[j] * std::polar(1.0, -2.0 * ameoto::constants::pi * static_cast<double>((j * k) % n) / static_cast<double>(n));
    return out;
}

}  // namespace

TEST_CASE("fft: equals the direct DFT for random complex input of every power-of-two size up to 512") {
    ameoto::Random rng(7);
    for (std::size_t n = 1; n <= 512; n <<= 1) {
        std::vector<std::complex<double>> x(n);
        for (auto& v : x) v = {rng.uniform() - 0.5, rng.uniform() - 0.5};
        const auto expected = direct_dft(x);
        fft_in_place(x);
        double worst = 0.0;
        for (std::size_t k = 0; k < n; ++k) worst = std::max(worst, std::abs(x[k] - expected[k]));
        // Both sums round about log2(n) (radix-2) or n (direct) times on values of order sqrt(n):
        // 1e-12 is some 1000 eps above either.
        CHECK_MESSAGE(worst < 1e-12, "n = " << n << ", worst difference " << worst);
    }
}

TEST_CASE("fft: a cosine at bin 5 of 64 lands in bins 5 and 59 with amplitude n/2; Parseval holds") {
    const std::size_t n = 64;
    std::vector<std::complex<double>> x(n);
    double energy = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        x[j] = std::cos(2.0 * ameoto::constants::pi * 5.0 * static_cast<double>(j) / n);
        energy += std::norm(x[j]);
    }
    fft_in_place(x);
    double spectral = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        spectral += std::norm(x[k]);
        const double expected = (k == 5 || k == n - 5) ? n / 2.0 : 0.0;
        CHECK(std::abs(x[k]) == doctest::Approx(expected).epsilon(1e-12).scale(1.0));
    }
    CHECK(spectral / n == ameoto::test::relative(energy).epsilon(1e-12));   // sum |x|^2 = (1/n) sum |X|^2
}

TEST_CASE("fft: a size that is not a power of two is refused") {
    std::vector<std::complex<double>> x(12);
    CHECK_THROWS_AS(fft_in_place(x), std::invalid_argument);
    std::vector<std::complex<double>> empty;
    CHECK_THROWS_AS(fft_in_place(empty), std::invalid_argument);
}
