// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/ear_measures.hpp"

#include <cmath>
#include <complex>
#include <stdexcept>

namespace ameoto::test {
namespace {

// In-place radix-2 FFT (a test's own, so the support library needs no engine).
void ear_fft(std::vector<std::complex<double>>& a, bool inverse) {
    const std::size_t n = a.size();
    if (n == 0 || (n & (n - 1)) != 0) throw std::invalid_argument("ear_fft: the length must be a power of two");
    for (std::size_t i = 1, j = 0; i < n; ++i) {
        std::size_t bit = n >> 1;
        for (; j & bit; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j) std::swap(a[i], a[j]);
    }
    const double pi = 3.14159265358979323846;
    for (std::size_t len = 2; len <= n; len <<= 1) {
        const double angle = (inverse ? 2.0 : -2.0) * pi / static_cast<double>(len);
        const std::complex<double> step(std::cos(angle), std::sin(angle));
        for (std::size_t i = 0; i < n; i += len) {
            std::complex<double> w(1.0);
            for (std::size_t k = 0; k < len / 2; ++k, w *= step) {
                const std::complex<double> u = a[i + k], v = a[i + k + len / 2] * w;
                a[i + k] = u + v;
                a[i + k + len / 2] = u - v;
            }
        }
    }
}

}  // namespace

double band_energy(const std::vector<float>& x, std::size_t from, std::size_t length, double rate_hz, double f_lo, double f_hi) {
    if (from + length > x.size()) throw std::invalid_argument("band_energy: the window runs past the signal");
    std::vector<std::complex<double>> a(length);
    for (std::size_t n = 0; n < length; ++n) a[n] = x[from + n];
    ear_fft(a, false);
    double e = 0.0;
    for (std::size_t k = 1; k < length / 2; ++k) {
        const double f = static_cast<double>(k) * rate_hz / static_cast<double>(length);
        if (f >= f_lo && f < f_hi) e += std::norm(a[k]);
    }
    return e;
}

double interaural_lag(const std::vector<float>& left, const std::vector<float>& right, std::size_t from, std::size_t length,
                      double rate_hz, double f_max, double max_lag_s) {
    if (from + length > left.size() || from + length > right.size())
        throw std::invalid_argument("interaural_lag: the window runs past the signal");
    const std::size_t n = 2 * length;
    std::vector<std::complex<double>> l(n), r(n);
    for (std::size_t i = 0; i < length; ++i) {
        l[i] = left[from + i];
        r[i] = right[from + i];
    }
    ear_fft(l, false);
    ear_fft(r, false);
    std::vector<std::complex<double>> c(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t folded = k <= n / 2 ? k : n - k;
        if (static_cast<double>(folded) * rate_hz / static_cast<double>(n) < f_max) c[k] = std::conj(l[k]) * r[k];
    }
    ear_fft(c, true);   // c[lag]: sum_t left[t] right[t + lag] (times n)
    const int max_lag = static_cast<int>(max_lag_s * rate_hz);
    const auto size = static_cast<long>(n);
    auto at = [&](int lag) { return c[static_cast<std::size_t>((lag + size) % size)].real(); };
    int peak = -max_lag;
    for (int lag = -max_lag; lag <= max_lag; ++lag)
        if (at(lag) > at(peak)) peak = lag;
    const double a = at(peak - 1), b = at(peak), cc = at(peak + 1);
    const double shift = (a - 2 * b + cc) != 0.0 ? 0.5 * (a - cc) / (a - 2 * b + cc) : 0.0;
    return (peak + shift) / rate_hz;
}

}  // namespace ameoto::test
