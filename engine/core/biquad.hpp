// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A second-order section: its coefficients, a Butterworth low- or high-pass section, its response at a
// point z of the plane, and its state run sample by sample (direct form I).
//
// Interface:
//   Biquad q = butterworth_section(/*high=*/false, fc_hz, rate_hz, quality);   // build phase
//   q.response(z)                      // H(z), for design and tests
//   BiquadState s; y = s.process(q, x);   // audio-safe: no allocation, arithmetic only
//
// The sections are Bristow-Johnson's audio EQ cookbook low- and high-pass: the analogue section of
// quality Q by the bilinear transform with the corner prewarped. A Butterworth filter of order 2N is N
// of them with Q = 1 / (2 cos((2k - 1) pi / (4N))), k = 1..N (order 2: Q = 1 / sqrt 2).

#include <complex>

#include "engine/core/physical_constants.hpp"

namespace ameoto {

struct Biquad {
    double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;   // a0 normalised to 1

    std::complex<double> response(std::complex<double> z) const {
        const std::complex<double> zi = 1.0 / z;
        return (b0 + b1 * zi + b2 * zi * zi) / (1.0 + a1 * zi + a2 * zi * zi);
    }
};

inline Biquad butterworth_section(bool high, double corner_hz, double rate_hz, double quality) {
    const double w0 = 2.0 * constants::pi * corner_hz / rate_hz;
    const double cw = std::cos(w0), alpha = std::sin(w0) / (2.0 * quality);
    const double a0 = 1.0 + alpha;
    Biquad q;
    if (high) {
        q.b0 = (1.0 + cw) / 2.0 / a0;
        q.b1 = -(1.0 + cw) / a0;
    } else {
        q.b0 = (1.0 - cw) / 2.0 / a0;
        q.b1 = (1.0 - cw) / a0;
    }
    q.b2 = q.b0;
    q.a1 = -2.0 * cw / a0;
    q.a2 = (1.0 - alpha) / a0;
    return q;
}

struct BiquadState {
    double x1 = 0.0, x2 = 0.0, y1 = 0.0, y2 = 0.0;
    double process(const Biquad& q, double x) {
        const double y = q.b0 * x + q.b1 * x1 + q.b2 * x2 - q.a1 * y1 - q.a2 * y2;
        x2 = x1;
        x1 = x;
        y2 = y1;
        y1 = y;
        return y;
    }
};

}  // namespace ameoto
