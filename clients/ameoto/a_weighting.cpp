// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/a_weighting.hpp"

#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace ameoto::client {

namespace {

// IEC 61672-1:2013, E.6 (the pole frequencies from E.4.1's approximations, as the standard prints them).
constexpr double f1 = 20.598997, f2 = 107.65265, f3 = 737.86223, f4 = 12194.217;

double analogue_magnitude(double f) {
    const double f2sq = f * f;
    const double num = f4 * f4 * f2sq * f2sq;
    const double den = (f2sq + f1 * f1) * std::sqrt((f2sq + f2 * f2) * (f2sq + f3 * f3)) * (f2sq + f4 * f4);
    return num / den;
}

}  // namespace

double a_weighting_db(double frequency_hz) {
    if (!(frequency_hz > 0.0)) return -INFINITY;
    return 20.0 * std::log10(analogue_magnitude(frequency_hz) / analogue_magnitude(1000.0));
}

AWeighting::AWeighting(double sample_rate) : sample_rate_(sample_rate) {
    if (!(sample_rate >= 8000.0 && sample_rate <= 768000.0))
        throw std::invalid_argument("A-weighting: sample rate must be 8 to 768 kHz");
    const double k = 2.0 * sample_rate;   // s = k (1 - z^-1) / (1 + z^-1)
    auto warped = [&](double f) { return k * std::tan(std::numbers::pi * f / sample_rate); };
    // s / (s + a) -> k (1 - z^-1) / ((k + a) + (a - k) z^-1)
    auto high_pass = [&](double f) {
        const double a = warped(f);
        return Section{k / (k + a), -k / (k + a), (a - k) / (k + a)};
    };
    // a / (s + a) -> a (1 + z^-1) / ((k + a) + (a - k) z^-1)
    auto low_pass = [&](double f) {
        const double a = warped(f);
        return Section{a / (k + a), a / (k + a), (a - k) / (k + a)};
    };
    // f4 above Nyquist (a sample rate under 24.4 kHz): tan() would fold it; the corner is left out, the
    // zeros and lower poles still weight what the band holds.
    const bool has_f4 = f4 < 0.45 * sample_rate;
    sections_ = {high_pass(f1), high_pass(f1), high_pass(f2), high_pass(f3),
                 has_f4 ? low_pass(f4) : Section{}, has_f4 ? low_pass(f4) : Section{}};
    gain_ = 1.0 / raw_response(1000.0);
}

double AWeighting::raw_response(double frequency_hz) const {
    const std::complex<double> z_inv = std::polar(1.0, -2.0 * std::numbers::pi * frequency_hz / sample_rate_);
    std::complex<double> h = 1.0;
    for (const Section& s : sections_) h *= (s.b0 + s.b1 * z_inv) / (1.0 + s.a1 * z_inv);
    return std::abs(h);
}

double AWeighting::response_db(double frequency_hz) const { return 20.0 * std::log10(gain_ * raw_response(frequency_hz)); }

void AWeighting::reset() {
    for (Section& s : sections_) s.x1 = s.y1 = 0.0;
}

}  // namespace ameoto::client
