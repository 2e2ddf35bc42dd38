// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Symplectic (semi-implicit) Euler, velocity first, with sub-steps.
//
// Interface: as ExplicitVerlet (init(arrays, T, sub_steps), step, reset, finite, position, velocity,
// energy).
//
// Scheme: v[n+1] = v[n] + T' M^-1 F(x[n], v[n]);  x[n+1] = x[n] + T' v[n+1],  F = ext - K x - C v.
// Eliminating v gives x[n+1] - 2 x[n] + x[n-1] = T'^2 M^-1 F(x[n], (x[n] - x[n-1]) / T'): algebraically
// the CORDIS scheme (explicit_verlet.hpp) with its backward-difference damping, so the same stability
// (omega^2 T'^2 + 2 gamma T' < 4) and the same warping: an undamped oscillator has
// z^2 - (2 - omega0^2 T'^2) z + 1 = 0, cos(omega T') = 1 - omega0^2 T'^2 / 2, i.e.
// omega = (2/T') asin(omega0 T' / 2). The position-first variant (x += T' v; v += T' M^-1 F(x[n+1]))
// has the same characteristic polynomial. What differs from ExplicitVerlet is the state kept (x, v
// instead of x[n], x[n-1]), hence rounding and the velocity reported: here v[n] is the velocity that
// moved x from x[n-1] to x[n], exactly the backward difference.
// It conserves the shadow energy H = 1/2 v'Mv + 1/2 x'K x - (T'/2) v'K x (undamped; Hairer, Lubich &
// Wanner, Geometric Numerical Integration, 2006, ch. IX), so the energy 1/2 v'Mv + 1/2 x'Kx oscillates
// by about omega T' / 2 and never drifts.

#include <vector>

#include "engine/core/integrators/network_arrays.hpp"

namespace ameoto {

class SymplecticEuler {
public:
    void init(const NetworkArrays& net, double output_step_s, int sub_steps);
    double step(const NetworkArrays& net, const double* ext);
    void reset();
    bool finite() const;
    double position(std::size_t i) const { return x_[i]; }
    double velocity(std::size_t i) const { return v_[i]; }
    double energy(const NetworkArrays& net) const { return net.energy(x_.data(), v_.data()); }

private:
    std::vector<double> x_, v_, force_;
    double dt_ = 0.0;
    int sub_steps_ = 1;
};

}  // namespace ameoto
