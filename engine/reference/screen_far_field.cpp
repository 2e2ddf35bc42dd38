// SPDX-License-Identifier: GPL-3.0-or-later
// The reference's field beyond its box, and third-octave band levels (screen_far_field.hpp).
#include "engine/reference/screen_far_field.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/fft.hpp"
#include "engine/core/physical_constants.hpp"

namespace ameoto::reference {

std::vector<double> double_layer_pressure(const std::vector<std::vector<double>>& force, const std::vector<Vec3>& positions,
                                          const std::vector<Vec3>& normals, double dt, Vec3 x, double c, int samples) {
    if (force.size() != positions.size() || normals.size() != positions.size())
        throw std::invalid_argument("double_layer_pressure: one force series, position and normal per node");
    std::vector<double> p(static_cast<std::size_t>(samples), 0.0);
    for (std::size_t i = 0; i < force.size(); ++i) {
        const std::vector<double>& f = force[i];
        const Vec3 d = x - positions[i];
        const double r = norm(d);
        if (!(r > 0.0)) continue;
        const double cos_theta = dot(d, normals[i]) / r;
        const double near = cos_theta / (4.0 * constants::pi * r * r), far = cos_theta / (4.0 * constants::pi * c * r);
        const auto n = static_cast<long>(f.size());
        // Series value at sample index s (time (s + 1) dt); 0 before the first.
        auto at = [&](long s) { return s >= 0 && s < n ? f[static_cast<std::size_t>(s)] : 0.0; };
        for (long k = 0; k < samples; ++k) {
            const double s = static_cast<double>(k) - r / (c * dt);   // retarded, in samples
            const auto s0 = static_cast<long>(std::floor(s));
            const double frac = s - static_cast<double>(s0);
            const double value = (1.0 - frac) * at(s0) + frac * at(s0 + 1);
            const double slope = ((1.0 - frac) * (at(s0 + 1) - at(s0 - 1)) + frac * (at(s0 + 2) - at(s0))) / (2.0 * dt);
            p[static_cast<std::size_t>(k)] += near * value + far * slope;
        }
    }
    return p;
}

double third_octave_filter_power(double centre_hz, double f_hz) {
    if (!(f_hz > 0.0)) return 0.0;
    const double q = 1.0 / (std::pow(2.0, 1.0 / 6.0) - std::pow(2.0, -1.0 / 6.0));
    const double x = q * (f_hz / centre_hz - centre_hz / f_hz);   // the low-pass prototype's frequency
    const double x2 = x * x;
    return 1.0 / (1.0 + x2 * x2 * x2);
}

namespace {

// The iec61260 levels (screen_far_field.hpp): one FFT of the record padded to at least 4 N samples.
std::vector<BandLevel> filtered_band_levels(const std::vector<double>& signal, double dt, double lo_hz, double hi_hz) {
    std::size_t size = 1;
    while (size < 4 * signal.size()) size *= 2;
    std::vector<std::complex<double>> x(size, 0.0);
    for (std::size_t n = 0; n < signal.size(); ++n) x[n] = signal[n];
    fft_in_place(x);
    const double df = 1.0 / (static_cast<double>(size) * dt);
    std::vector<BandLevel> out;
    for (int k = -20; k <= 13; ++k) {
        const double centre = 1000.0 * std::pow(2.0, k / 3.0);
        if (centre < lo_hz / 1.06 || centre > hi_hz * 1.06) continue;
        const auto first = static_cast<std::size_t>(std::max(1.0, std::floor(centre / 4.0 / df)));
        const auto last = std::min(size / 2, static_cast<std::size_t>(std::ceil(4.0 * centre / df)));
        double energy = 0.0;
        for (std::size_t b = first; b <= last; ++b)
            energy += 2.0 * std::norm(x[b] * dt) * third_octave_filter_power(centre, static_cast<double>(b) * df) * df;
        out.push_back({centre, 10.0 * std::log10(std::max(energy, 1e-300))});
    }
    return out;
}

}  // namespace

std::vector<BandLevel> third_octave_levels(const std::vector<double>& signal, double dt, double lo_hz, double hi_hz, BandFilter filter) {
    if (signal.empty() || !(dt > 0.0)) throw std::invalid_argument("third_octave_levels: an empty signal");
    if (filter == BandFilter::iec61260) return filtered_band_levels(signal, dt, lo_hz, hi_hz);
    const double n = static_cast<double>(signal.size());
    const double df = 1.0 / (4.0 * n * dt);
    std::vector<BandLevel> out;
    for (int k = -20; k <= 13; ++k) {
        const double centre = 1000.0 * std::pow(2.0, k / 3.0);
        if (centre < lo_hz / 1.06 || centre > hi_hz * 1.06) continue;
        const double f_lo = centre * std::pow(2.0, -1.0 / 6.0), f_hi = centre * std::pow(2.0, 1.0 / 6.0);
        double energy = 0.0;
        for (double f = f_lo + 0.5 * df; f < f_hi; f += df) {
            // X(f) = sum x_n e^{-i 2 pi f n dt} dt, by a rotating phasor (renormalised each step).
            const std::complex<double> step = std::polar(1.0, -2.0 * constants::pi * f * dt);
            std::complex<double> w = 1.0, x = 0.0;
            for (const double v : signal) {
                x += v * w;
                w *= step;
            }
            energy += 2.0 * std::norm(x * dt) * df;
        }
        out.push_back({centre, 10.0 * std::log10(std::max(energy, 1e-300))});
    }
    return out;
}

}  // namespace ameoto::reference
