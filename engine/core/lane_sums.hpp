// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Long sums of products, kept as eight running sums (two 4-lane vectors) instead of one, for the modal
// canopy's per-sample reductions over its modes (air_canopy.hpp: a node read through its shapes;
// dipole_radiation.hpp: each channel's taps).
//
// Interface (any thread; no allocation):
//   double s = lane_sums::dot(a, b, n);              // sum a[k] b[k]
//   double s = lane_sums::dot2(a, x, b, y, n);       // sum a[k] x[k] + b[k] y[k]
//   double s = lane_sums::abs_dot(w, x, n);          // sum w[k] |x[k]|
//
// Why: one running sum is one chain of dependent additions (about 4 cycles each), so 400 modes cost
// some 1600 cycles a reading however wide the machine; eight independent chains let the additions
// overlap. The compiler may not reorder a floating-point sum itself (no -ffast-math), so the order is
// this code's: term k goes to running sum k mod 8 (k < n - n mod 8), the eight are added pairwise
// ((s0 + s4) + (s2 + s6)) + ((s1 + s5) + (s3 + s7)), then the last n mod 8 terms in turn. The vectors are
// GCC's vector extensions (the baseline build runs them as SSE2 pairs), with no fused multiply-add: the
// same bits on every x86-64.

#include <cstddef>
#include <cstring>

namespace ameoto::lane_sums {

namespace detail {

// The vectors never cross a function boundary (an AVX-sized argument or result changes the ABI on the
// baseline build): each loop loads, multiplies and adds in place.
using v4d = double __attribute__((vector_size(32)));
using v4u = unsigned long long __attribute__((vector_size(32)));

// One kernel for all three: sum over k of (w[k] * f(x[k]) + b[k] * y[k]), b and y optional.
template <bool magnitude, bool second>
double lanes(const double* w, const double* x, const double* b, const double* y, std::size_t n) {
    constexpr unsigned long long sign_off = 0x7fffffffffffffffULL;
    v4d lo{}, hi{};
    std::size_t k = 0;
    for (; k + 8 <= n; k += 8) {
        v4d w0, w1, x0, x1;
        std::memcpy(&w0, w + k, sizeof w0);
        std::memcpy(&w1, w + k + 4, sizeof w1);
        std::memcpy(&x0, x + k, sizeof x0);
        std::memcpy(&x1, x + k + 4, sizeof x1);
        if constexpr (magnitude) {
            x0 = (v4d)((v4u)x0 & v4u{sign_off, sign_off, sign_off, sign_off});
            x1 = (v4d)((v4u)x1 & v4u{sign_off, sign_off, sign_off, sign_off});
        }
        if constexpr (second) {
            v4d b0, b1, y0, y1;
            std::memcpy(&b0, b + k, sizeof b0);
            std::memcpy(&b1, b + k + 4, sizeof b1);
            std::memcpy(&y0, y + k, sizeof y0);
            std::memcpy(&y1, y + k + 4, sizeof y1);
            lo += w0 * x0 + b0 * y0;
            hi += w1 * x1 + b1 * y1;
        } else {
            lo += w0 * x0;
            hi += w1 * x1;
        }
    }
    // ((s0 + s4) + (s2 + s6)) + ((s1 + s5) + (s3 + s7)): s0..s3 in lo, s4..s7 in hi.
    const v4d s4 = lo + hi;
    double s = (s4[0] + s4[2]) + (s4[1] + s4[3]);
    for (; k < n; ++k) {
        const double xk = magnitude ? (x[k] < 0.0 ? -x[k] : x[k]) : x[k];
        if constexpr (second) s += w[k] * xk + b[k] * y[k];
        else s += w[k] * xk;
    }
    return s;
}

}  // namespace detail

inline double dot(const double* a, const double* b, std::size_t n) { return detail::lanes<false, false>(a, b, nullptr, nullptr, n); }

inline double dot2(const double* a, const double* x, const double* b, const double* y, std::size_t n) {
    return detail::lanes<false, true>(a, x, b, y, n);
}

inline double abs_dot(const double* w, const double* x, std::size_t n) { return detail::lanes<true, false>(w, x, nullptr, nullptr, n); }

}  // namespace ameoto::lane_sums
