// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The discrete Fourier transform, for analysis off the audio thread (the texture tier's calibration,
// benchmarks and tests); nothing on the audio path uses it.
//
// Interface:
//   std::vector<std::complex<double>> a(n);   // n a power of two (checked: std::invalid_argument)
//   fft_in_place(a);                          // a[k] = sum_j a[j] exp(-2 pi i j k / n), unnormalised
//
// Iterative radix-2 Cooley-Tukey: bit-reversal permutation, then log2 n butterfly stages whose twiddle
// factor is advanced by multiplication (w_len = exp(-2 pi i / len)); the rounding error this
// accumulates, about n eps relative, is far below what an analysis of audio at 1e-16 needs.

#include <complex>
#include <vector>

namespace ameoto {

void fft_in_place(std::vector<std::complex<double>>& a);

}  // namespace ameoto
