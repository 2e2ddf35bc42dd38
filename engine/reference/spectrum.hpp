// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Spectral helpers of the air reference (engine/reference): a direct Fourier transform at any frequency
// (the validations' signals are short and compact, so no windowing is needed for ratios), and the
// frequency of a signal's largest peak in a band (Hann window, golden-section refinement).
//
// Interface:
//   std::complex<double> X = fourier_at(samples, dt, t0, f);   // sum x_n exp(-i 2 pi f (t0 + n dt)) dt
//   double f = peak_frequency(samples, dt, f_lo, f_hi);       // Hz; the band's highest |X| (Hann window)

#include <complex>
#include <vector>

namespace ameoto::reference {

std::complex<double> fourier_at(const std::vector<double>& samples, double dt, double t0, double frequency_hz,
                                bool hann = false);
double peak_frequency(const std::vector<double>& samples, double dt, double f_lo, double f_hi);

}  // namespace ameoto::reference
