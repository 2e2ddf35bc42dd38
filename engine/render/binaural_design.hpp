// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The pieces the binaural decoder (binaural_decoder.hpp) is designed from, off the audio thread: the
// virtual loudspeaker grid, the AmbiX spherical harmonics it decodes with, the per-order weights and the
// crossover that splits them into two bands. Pure functions, any thread (they allocate).
//
// Interface:
//   lebedev_50()                          // 50 unit vectors and weights (sum 1)
//   ambix_sn3d(order, x, y, z, out)       // out[acn], acn 0..(order+1)^2-1, ACN / SN3D / no Condon-Shortley
//   max_re_weights(order)                 // g_0..g_N, energy-normalised
//   linkwitz_riley_4(x, fc, rate, lp, hp) // x through LR4's low-pass and high-pass (in phase, sum all-pass)
//   linkwitz_riley_4_tail(fc, rate, eps)  // samples after which LR4's responses stay below eps of their peak
//   minimum_phase_fir(magnitude, taps)    // the minimum-phase FIR of a magnitude response (bins 0..K/2)

#include <array>
#include <vector>

namespace ameoto::binaural_design {

struct SpherePoint {
    double x, y, z;   // unit vector: x front, y left, z up (AmbiX's and SOFA's listener axes)
    double weight;    // quadrature weight, the grid's weights sum to 1 (the integral over the sphere / 4 pi)
};

// Lebedev & Laikov (1999), "A quadrature formula for the sphere of the 131st algebraic order of accuracy",
// Doklady Mathematics 59(3): the 50-point rule, exact for polynomials of degree <= 11 (octahedral orbits
// a1 (6), a2 (12), a3 (8) and b1 (24) with l = 1/sqrt(11), m = 3/sqrt(11)).
std::vector<SpherePoint> lebedev_50();

// Real spherical harmonics Y_n^m of orders 0..order (<= 3) in AmbiX's convention (Nachbar, Zotter, Deleflie
// & Sontacchi 2011, "AmbiX - a suggested Ambisonics format", table 1): ACN = n^2 + n + m, Schmidt
// semi-normalised (SN3D: Y_0^0 = 1 and sum_m Y_n^m(u)^2 = 1), no Condon-Shortley phase, as polynomials in
// the unit vector (x, y, z). Throws std::invalid_argument for an order outside 0..3.
void ambix_sn3d(int order, double x, double y, double z, double* out);

// max-rE weights g_n = P_n(cos(137.9 deg / (N + 1.51))) (Zotter & Frank 2012, JAES 60(10), eq. 10), scaled
// by sqrt((N+1)^2 / sum_n (2n+1) g_n^2) so a plane wave keeps the basic decode's energy.
std::vector<double> max_re_weights(int order);

// 4th-order Linkwitz-Riley crossover at fc: two cascaded 2nd-order Butterworth sections each way, by the
// bilinear transform with the cut-off prewarped (Bristow-Johnson's audio EQ cookbook, Q = 1/sqrt 2). LP and
// HP are in phase at every frequency and LP + HP is an all-pass (Linkwitz 1976, JAES 24(1)).
void linkwitz_riley_4(const std::vector<double>& x, double fc_hz, double rate_hz, std::vector<double>& lp,
                      std::vector<double>& hp);
int linkwitz_riley_4_tail(double fc_hz, double rate_hz, double eps);

// The minimum-phase impulse response whose magnitude is `magnitude` (K/2 + 1 bins of a K-point DFT, K a power
// of two, every value > 0), by the real cepstrum folded onto positive quefrencies (Oppenheim & Schafer,
// "Discrete-time signal processing", 3rd ed., section 5.6 / 13.8), cut to `taps` with a half-Hann fade over
// its last quarter. Throws std::invalid_argument for a bad size.
std::vector<double> minimum_phase_fir(const std::vector<double>& magnitude, int taps);

}  // namespace ameoto::binaural_design
