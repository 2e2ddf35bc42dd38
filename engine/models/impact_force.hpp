// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The force a drop exerts on a surface while it spreads, as a fixed-capacity pool of pulses.
//
// Interface:
//   ImpactPool pool;                                  // fixed capacity, no allocation
//   pool.add(target, impulse_N_s, duration_s, dt)     // false when full (the caller counts it)
//   pool.emit(dt, sink)                               // calls sink(target, force_N) for each active pulse
//   pool.active()                                     // pulses under way
//
// Model (../shared/reference/physics.md section 4, Soto et al. 2014; Gordillo et al. 2018): a drop of
// mass m and speed V on a rigid surface pushes with a force that rises like t^(1/2) and lasts a time of
// order D / V, with impulse m V when it does not rebound. We use f(t) = J (15 / 4 tau) s^(1/2) (1 - s),
// s = t / tau, tau = D / V, whose integral is J and whose peak, 0.755 rho V^2 D^2, matches the published
// 0.8 rho V^2 D^2 within 6 %. Each sample delivers the shape's exact integral over that sample,
// J (F(s1) - F(s0)) with F(s) = 5/2 s^(3/2) - 3/2 s^(5/2), so the force never pulls; the last sample
// delivers whatever is left over, so the impulse is exact to rounding at any sample rate.

#include <array>
#include <cmath>

#include "engine/models/canopy.hpp"

namespace ameoto {

struct ImpactPulse {
    CanopyHit target;
    double impulse = 0.0;      // N s
    double delivered = 0.0;    // N s so far
    int samples = 1;           // duration in samples
    int elapsed = 0;
};

class ImpactPool {
public:
    static constexpr int capacity = 2048;

    bool add(CanopyHit target, double impulse, double duration_s, double dt) {
        if (count_ == capacity) return false;
        ImpactPulse& p = pulses_[static_cast<std::size_t>(count_++)];
        p.target = target;
        p.impulse = impulse;
        p.delivered = 0.0;
        const double samples = std::ceil(duration_s / dt);
        p.samples = samples < 1.0 ? 1 : (samples > 1e6 ? 1000000 : static_cast<int>(samples));
        p.elapsed = 0;
        return true;
    }

    template <typename Sink>
    void emit(double dt, Sink&& sink) {
        for (int i = 0; i < count_;) {
            ImpactPulse& p = pulses_[static_cast<std::size_t>(i)];
            double impulse_now;
            if (p.elapsed + 1 >= p.samples) {
                impulse_now = p.impulse - p.delivered;
            } else {
                const double s0 = static_cast<double>(p.elapsed) / p.samples;
                const double s1 = static_cast<double>(p.elapsed + 1) / p.samples;
                impulse_now = p.impulse * (shape_integral(s1) - shape_integral(s0));
            }
            p.delivered += impulse_now;
            sink(p.target, impulse_now / dt);
            if (++p.elapsed >= p.samples) {
                pulses_[static_cast<std::size_t>(i)] = pulses_[static_cast<std::size_t>(--count_)];
            } else {
                ++i;
            }
        }
    }

    int active() const { return count_; }
    void clear() { count_ = 0; }

private:
    // Integral of (15/4) s^(1/2) (1 - s) from 0 to s; 1 at s = 1.
    static double shape_integral(double s) { return s * std::sqrt(s) * (2.5 - 1.5 * s); }

    std::array<ImpactPulse, capacity> pulses_{};
    int count_ = 0;
};

}  // namespace ameoto
