// SPDX-License-Identifier: GPL-3.0-or-later
// The binaural decoder's design pieces (engine/render/binaural_design.hpp): the Lebedev grid integrates what
// it claims, the AmbiX harmonics are SN3D and orthogonal, the max-rE weights and the crossover behave.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "engine/render/binaural_design.hpp"

using namespace ameoto;
using namespace ameoto::binaural_design;

namespace {

double lebedev_double_factorial(int n) {   // n!! for odd n >= -1
    double r = 1.0;
    for (int k = n; k > 1; k -= 2) r *= k;
    return r;
}

}  // namespace

TEST_CASE("lebedev_50: 50 unit vectors whose rule integrates every monomial up to degree 11 exactly") {
    const auto grid = lebedev_50();
    REQUIRE(grid.size() == 50);
    double total = 0.0;
    for (const auto& p : grid) {
        CHECK(std::abs(p.x * p.x + p.y * p.y + p.z * p.z - 1.0) < 1e-15);
        total += p.weight;
    }
    CHECK(std::abs(total - 1.0) < 1e-14);   // the weights are tabulated to 16 digits
    // The mean of x^2a y^2b z^2c over the sphere is (2a-1)!! (2b-1)!! (2c-1)!! / (2(a+b+c)+1)!! (Folland 2001,
    // "How to integrate a polynomial over a sphere"); odd powers average to 0. Every degree <= 11.
    for (int i = 0; i <= 11; ++i)
        for (int j = 0; i + j <= 11; ++j)
            for (int k = 0; i + j + k <= 11; ++k) {
                double sum = 0.0;
                for (const auto& p : grid) sum += p.weight * std::pow(p.x, i) * std::pow(p.y, j) * std::pow(p.z, k);
                double exact = 0.0;
                if (i % 2 == 0 && j % 2 == 0 && k % 2 == 0)
                    exact = lebedev_double_factorial(i - 1) * lebedev_double_factorial(j - 1) * lebedev_double_factorial(k - 1) /
                            lebedev_double_factorial(i + j + k + 1);
                INFO("x^" << i << " y^" << j << " z^" << k);
                CHECK(std::abs(sum - exact) < 1e-14);
            }
}

TEST_CASE("ambix_sn3d: on the grid the order-3 harmonics are orthogonal with SN3D norms 1/(2n+1)") {
    // SN3D: the mean of (Y_n^m)^2 over the sphere is 1/(2n+1) (Nachbar et al. 2011, eq. 4); the rule is exact
    // for these degree-6 products, so the sums hold to rounding.
    const auto grid = lebedev_50();
    std::vector<double> y(16);
    std::vector<double> gram(256, 0.0);
    for (const auto& p : grid) {
        ambix_sn3d(3, p.x, p.y, p.z, y.data());
        for (int a = 0; a < 16; ++a)
            for (int b = 0; b < 16; ++b) gram[static_cast<std::size_t>(a * 16 + b)] += p.weight * y[static_cast<std::size_t>(a)] * y[static_cast<std::size_t>(b)];
    }
    for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b) {
            const int n = static_cast<int>(std::sqrt(a + 0.5));
            INFO("ACN " << a << " x ACN " << b);
            CHECK(std::abs(gram[static_cast<std::size_t>(a * 16 + b)] - (a == b ? 1.0 / (2 * n + 1) : 0.0)) < 1e-14);
        }
    // No Condon-Shortley phase: Y_1^1 = x, positive towards the front; Y_1^-1 = y, positive to the left.
    ambix_sn3d(1, 1, 0, 0, y.data());
    CHECK(y[3] == 1.0);
    ambix_sn3d(1, 0, 1, 0, y.data());
    CHECK(y[1] == 1.0);
    CHECK_THROWS(ambix_sn3d(4, 1, 0, 0, y.data()));
}

TEST_CASE("max_re_weights: Zotter & Frank's values, energy-normalised") {
    // Order 1: g_1 / g_0 = P_1(cos(137.9 deg / 2.51)) = 0.5755 (Zotter & Frank 2012, eq. 10; the exact 3-D
    // first-order maximum of rE is 1/sqrt(3) = 0.5774, Daniel 2001); the energy sum (2n+1) g_n^2 = (N+1)^2;
    // the weights fall with the order.
    for (int order = 1; order <= 3; ++order) {
        const auto g = max_re_weights(order);
        double energy = 0.0;
        for (int n = 0; n <= order; ++n) energy += (2 * n + 1) * g[static_cast<std::size_t>(n)] * g[static_cast<std::size_t>(n)];
        CHECK(std::abs(energy - (order + 1.0) * (order + 1.0)) < 1e-12);
        for (int n = 1; n <= order; ++n) CHECK(g[static_cast<std::size_t>(n)] < g[static_cast<std::size_t>(n - 1)]);
    }
    const auto g1 = max_re_weights(1);
    CHECK(std::abs(g1[1] / g1[0] - std::cos(137.9 / 2.51 * 3.14159265358979323846 / 180.0)) < 1e-12);
    CHECK(std::abs(g1[1] / g1[0] - 1.0 / std::sqrt(3.0)) < 0.005);   // the approximation's stated accuracy
}

TEST_CASE("linkwitz_riley_4: LP + HP is an all-pass, each -6 dB at the crossover") {
    const double rate = 48000.0, fc = 1000.0;
    const int n = 8192;
    std::vector<double> impulse(n, 0.0), lp, hp;
    impulse[0] = 1.0;
    linkwitz_riley_4(impulse, fc, rate, lp, hp);
    // Magnitudes at a few frequencies by direct DFT sums (the responses have decayed far below 1e-12 by n).
    auto magnitude = [&](const std::vector<double>& h, double f) {
        double re = 0, im = 0;
        for (int t = 0; t < n; ++t) {
            re += h[static_cast<std::size_t>(t)] * std::cos(2 * 3.14159265358979323846 * f * t / rate);
            im -= h[static_cast<std::size_t>(t)] * std::sin(2 * 3.14159265358979323846 * f * t / rate);
        }
        return std::hypot(re, im);
    };
    std::vector<double> sum(n);
    for (int t = 0; t < n; ++t) sum[static_cast<std::size_t>(t)] = lp[static_cast<std::size_t>(t)] + hp[static_cast<std::size_t>(t)];
    for (double f : {50.0, 300.0, 1000.0, 3000.0, 15000.0}) CHECK(std::abs(magnitude(sum, f) - 1.0) < 1e-9);
    CHECK(std::abs(20 * std::log10(magnitude(lp, fc)) + 6.0206) < 1e-6);   // LR4: -6.02 dB each at fc
    CHECK(std::abs(20 * std::log10(magnitude(hp, fc)) + 6.0206) < 1e-6);
    CHECK(magnitude(lp, 8 * fc) < 1e-3);   // 24 dB/octave: -72 dB three octaves up (bilinear: steeper)
    const int tail = linkwitz_riley_4_tail(fc, rate, 1e-6);
    CHECK(tail > 50);
    CHECK(tail < 1000);
}

TEST_CASE("minimum_phase_fir: the magnitude asked for, its energy at the start") {
    // A smooth high shelf, +10 dB above ~4 kHz at 48 kHz (K = 1024): the FIR's DFT magnitude must match it to
    // 0.1 dB (the 5 ms cut and fade of a response that decays within ~1 ms change it far less), and a
    // minimum-phase response has the most energy of any with that magnitude in its first samples (Oppenheim &
    // Schafer, section 5.6): over half in the first 8 taps here, where a linear-phase one would be centred.
    const int K = 1024;
    std::vector<double> mag(K / 2 + 1);
    for (int k = 0; k <= K / 2; ++k) {
        const double f = k * 48000.0 / K;
        mag[static_cast<std::size_t>(k)] = std::pow(10.0, 0.5 * (1.0 + std::tanh((f - 4000.0) / 1500.0)) * 10.0 / 20.0);
    }
    const auto h = minimum_phase_fir(mag, 240);
    REQUIRE(h.size() == 240);
    for (int k : {0, 20, 85, 100, 300, 512}) {
        double re = 0, im = 0;
        for (std::size_t t = 0; t < h.size(); ++t) {
            re += h[t] * std::cos(2 * 3.14159265358979323846 * k * static_cast<double>(t) / K);
            im -= h[t] * std::sin(2 * 3.14159265358979323846 * k * static_cast<double>(t) / K);
        }
        INFO("bin " << k);
        CHECK(std::abs(20 * std::log10(std::hypot(re, im) / mag[static_cast<std::size_t>(k)])) < 0.1);
    }
    double head = 0, total = 0;
    for (std::size_t t = 0; t < h.size(); ++t) {
        total += h[t] * h[t];
        if (t < 8) head += h[t] * h[t];
    }
    CHECK(head > 0.5 * total);
    CHECK_THROWS(minimum_phase_fir(std::vector<double>(100, 1.0), 10));   // 99 x 2 is not a power of two
}
