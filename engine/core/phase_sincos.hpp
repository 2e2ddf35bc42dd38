// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The sine and cosine of a phase together, without a call into libm, for build-phase loops that take
// millions of them (the radiation damping's far-field phases, air_loading.cpp): a loop over an array
// of phases compiles to vector code, where std::sin and std::cos are one call each per element.
//
// Interface (any thread; no allocation):
//   double s, c;
//   phase_sincos(x, s, c);   // |x| <= phase_sincos_limit; within 2e-16 of sin(x), cos(x) (tested)
//
// Method (Cephes' sin.c and cos.c, S. L. Moshier, 1984-1995; Moshier, Methods and Programs for
// Mathematical Functions, 1989): x = n pi/2 + y with n the nearest integer to x 2/pi and y taken in three parts of pi/2
// (Cody & Waite, Software Manual for the Elementary Functions, 1980), so y is exact to a few ulp for
// |n| < 2^20; then sin and cos of y on [-pi/4, pi/4] by Cephes' minimax polynomials (relative error
// about 2e-16), and the quadrant n mod 4 picks and signs them. Past the limit the reduction loses bits:
// the caller keeps its phases within it (the canopy's far field: |k r| under 100).

#include <bit>
#include <cstdint>

namespace ameoto {

inline constexpr double phase_sincos_limit = 1.0e5;   // rad

inline void phase_sincos(double x, double& sine, double& cosine) {
    constexpr double two_over_pi = 0.63661977236758134308;
    // pi / 2 in three parts, the first two with trailing zero bits so that n times each is exact.
    constexpr double pio2_1 = 1.57079625129699707031E0, pio2_2 = 7.54978941586159635335E-8, pio2_3 = 5.39030285815811905290E-15;
    // The nearest integer by the 1.5 x 2^52 shift (round to nearest even, the default mode): its low
    // mantissa bits are then n in two's complement. No call, no conversion: all of it vectorises.
    constexpr double shift = 6755399441055744.0;
    const double shifted = x * two_over_pi + shift;
    const double n = shifted - shift;
    const std::uint64_t quadrant = std::bit_cast<std::uint64_t>(shifted) & 3u;
    const double y = ((x - n * pio2_1) - n * pio2_2) - n * pio2_3;
    const double z = y * y;
    const double s = y + y * z * (((((1.58962301576546568060E-10 * z - 2.50507477628578072866E-8) * z + 2.75573136213857245213E-6) * z -
                                    1.98412698295895385996E-4) * z + 8.33333333332211858878E-3) * z - 1.66666666666666307295E-1);
    const double c = 1.0 - 0.5 * z + z * z * (((((-1.13585365213876817300E-11 * z + 2.08757008419747316778E-9) * z -
                                                 2.75573141792967388112E-7) * z + 2.48015872888517045348E-5) * z -
                                               1.38888888888730564116E-3) * z + 4.16666666666665929218E-2);
    // n mod 4 = 0: (s, c); 1: (c, -s); 2: (-s, -c); 3: (-c, s): a swap for odd n, then sign bits.
    const std::uint64_t swap = 0u - (quadrant & 1u);   // all ones for odd n
    const std::uint64_t sb = std::bit_cast<std::uint64_t>(s), cb = std::bit_cast<std::uint64_t>(c);
    const std::uint64_t first = (cb & swap) | (sb & ~swap), second = (sb & swap) | (cb & ~swap);
    sine = std::bit_cast<double>(first ^ ((quadrant & 2u) << 62));
    cosine = std::bit_cast<double>(second ^ (((quadrant + 1u) & 2u) << 62));
}

}  // namespace ameoto
