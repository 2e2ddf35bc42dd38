// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the two ears of a binaural stream say about where a sound is: the level difference in a band and
// the time difference by cross-correlation, on the samples that came out (the live stream's WAV, a render's).
//
// Interface:
//   double e = band_energy(left, from, length, rate, 2000, 20000);   // length a power of two
//   double itd = interaural_lag(left, right, from, length, rate, f_max);   // s; > 0: the right ear later
//
// interaural_lag: the peak of the cross-correlation of the ears over +-1.5 ms, from their cross-spectrum
// L* R restricted to f < f_max (zero-padded to twice the length: linear, not circular), refined by a
// parabola through the peak and its neighbours. The band limit: the interaural time difference is a
// low-frequency cue (Wightman & Kistler 1992, JASA 91(3)), and an order-N Ambisonic decode reproduces the
// ears' signals only below N c / (2 pi r) (docs/binaural.md); above it the far ear hears the virtual
// speakers on its own side first and the broadband peak moves to ~0.1 ms.
// (The decoder's own test, tests/engine/render/binaural_decoder_test.cpp, measures a plane wave the same way.)

#include <cstddef>
#include <vector>

namespace ameoto::test {

double band_energy(const std::vector<float>& x, std::size_t from, std::size_t length, double rate_hz, double f_lo, double f_hi);
double interaural_lag(const std::vector<float>& left, const std::vector<float>& right, std::size_t from, std::size_t length,
                      double rate_hz, double f_max, double max_lag_s = 0.0015);

}  // namespace ameoto::test
