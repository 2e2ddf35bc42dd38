// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Backward (implicit) Euler, factored once.
//
// Interface: as ExplicitVerlet, init(arrays, T) (no sub-steps: unconditionally stable).
//
// Scheme: M (v[n+1] - v[n]) / T = f - C v[n+1] - K x[n+1],  x[n+1] = x[n] + T v[n+1]. Substituting x[n+1]:
//   (M + T C + T^2 K) v[n+1] = M v[n] + T (f - K x[n]).
// The system matrix M + T C + T^2 K is symmetric positive definite, factored once at init (sparse LDLT).
// The force applied for the step is taken at its end (f at t_{n+1}); the impulse over the step is T f.
// Properties (physics.md section 3): unconditionally stable (L-stable); it adds numerical damping that
// grows with omega T: an undamped oscillator's poles are 1 / (1 -+ i omega0 T), modulus
// 1 / sqrt(1 + omega0^2 T^2) per step, so its energy decreases monotonically: with no force,
// E[n+1] - E[n] = -1/2 (dv' M dv + dx' K dx) - T v[n+1]' C v[n+1] <= 0 (dv, dx the step's increments).
// Frequency: the pole angle atan(omega0 T) / T.
// Net force: sum_i m_i (v_i[n+1] - v_i[n]) / T.

#include <vector>

#include "engine/core/integrators/network_arrays.hpp"
#include "engine/core/integrators/sparse_ldlt.hpp"

namespace ameoto {

class BackwardEuler {
public:
    void init(const NetworkArrays& net, double time_step_s);
    double step(const NetworkArrays& net, const double* ext);
    void reset();
    bool finite() const;
    double position(std::size_t i) const { return x_[i]; }
    double velocity(std::size_t i) const { return v_[i]; }
    double energy(const NetworkArrays& net) const { return net.energy(x_.data(), v_.data()); }

private:
    std::vector<double> x_, v_, rhs_, v_next_;
    SparseLdlt solver_;
    double dt_ = 0.0;
};

}  // namespace ameoto
