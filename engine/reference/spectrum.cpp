// SPDX-License-Identifier: GPL-3.0-or-later
// Spectral helpers of the air reference: see spectrum.hpp.
#include "engine/reference/spectrum.hpp"

#include <cmath>

#include "engine/core/physical_constants.hpp"

namespace ameoto::reference {

std::complex<double> fourier_at(const std::vector<double>& samples, double dt, double t0, double frequency_hz,
                                bool hann) {
    const double w = 2.0 * constants::pi * frequency_hz;
    // Rotate a phasor instead of calling sin/cos per sample (renormalised every 1024 samples).
    const std::complex<double> turn = std::polar(1.0, -w * dt);
    std::complex<double> phase = std::polar(1.0, -w * t0), sum = 0.0;
    const std::size_t n = samples.size();
    for (std::size_t q = 0; q < n; ++q) {
        double x = samples[q];
        if (hann && n > 1) x *= 0.5 - 0.5 * std::cos(2.0 * constants::pi * static_cast<double>(q) / static_cast<double>(n - 1));
        sum += x * phase;
        phase *= turn;
        if ((q & 1023) == 1023) phase /= std::abs(phase);
    }
    return sum * dt;
}

double peak_frequency(const std::vector<double>& samples, double dt, double f_lo, double f_hi) {
    auto magnitude = [&](double f) { return std::abs(fourier_at(samples, dt, 0.0, f, true)); };
    const double duration = dt * static_cast<double>(samples.size());
    const double step = 1.0 / (8.0 * duration);
    double best_f = f_lo, best = -1.0;
    for (double f = f_lo; f <= f_hi; f += step) {
        const double m = magnitude(f);
        if (m > best) best = m, best_f = f;
    }
    // Golden section on [best_f - step, best_f + step].
    double a = best_f - step, b = best_f + step;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - g * (b - a), d = a + g * (b - a), mc = magnitude(c), md = magnitude(d);
    for (int it = 0; it < 40; ++it) {
        if (mc > md) b = d, d = c, md = mc, c = b - g * (b - a), mc = magnitude(c);
        else a = c, c = d, mc = md, d = a + g * (b - a), md = magnitude(d);
    }
    return 0.5 * (a + b);
}

}  // namespace ameoto::reference
