// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The exact free decay of one damped mode over a step, for the modal integrators (integrators/modal.hpp,
// models/air_canopy.hpp): q'' + 2 s q' + omega^2 q = 0 advanced by T has the transition
//   [q, q'](T) = [[ec + s es, es], [-omega^2 es, ec - s es]] [q, q'](0)
// with ec = e^{-sT} cos(wd T), es = e^{-sT} sin(wd T) / wd, wd^2 = omega^2 - s^2.
//
// Interface (any thread; pure, no allocation):
//   ModeDecay d = mode_decay(omega_rad_s, rate_per_s, step_s);
// Written so that neither overflows (strongly overdamped: e^{-sT} cosh(mu T) as a sum of decaying
// exponentials) nor divides by zero (critically damped: the series of sin(x)/x and cosh).

#include <cmath>

namespace ameoto {

struct ModeDecay {
    double ec, es;
};

inline ModeDecay mode_decay(double omega, double s, double t) {
    const double d = omega * omega - s * s;   // wd^2
    const double e = std::exp(-s * t);
    if (std::abs(d) * t * t < 1e-12) {
        // sin(x)/x and cosh: second-order series, error ~ (|d| T^2)^2 / 120 < 1e-26.
        return {e * (1.0 - 0.5 * d * t * t), e * t * (1.0 - d * t * t / 6.0)};
    }
    if (d > 0.0) {
        const double wd = std::sqrt(d);
        return {e * std::cos(wd * t), e * std::sin(wd * t) / wd};
    }
    const double mu = std::sqrt(-d);
    // s - mu = omega^2 / (s + mu) without cancellation.
    const double slow = std::exp(-(omega * omega / (s + mu)) * t), fast = std::exp(-(s + mu) * t);
    return {0.5 * (slow + fast), 0.5 * (slow - fast) / mu};
}

}  // namespace ameoto
