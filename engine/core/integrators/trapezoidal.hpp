// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The trapezoidal rule (Newmark average acceleration, beta = 1/4, gamma = 1/2), factored once.
//
// Interface: as ExplicitVerlet, init(arrays, T) (no sub-steps: unconditionally stable).
//
// Scheme (Newmark 1959, beta = 1/4, gamma = 1/2; for M x'' + C x' + K x = f it is the trapezoidal
// rule on (x, v)):
//   x[n+1] = x[n] + T v[n] + (T^2/4)(a[n] + a[n+1])
//   v[n+1] = v[n] + (T/2)(a[n] + a[n+1])
//   M a[n+1] + C v[n+1] + K x[n+1] = f.
// Substituting the first two into the third, with the predictors x* = x[n] + T v[n] + (T^2/4) a[n] and
// v* = v[n] + (T/2) a[n]:
//   (M + (T/2) C + (T^2/4) K) a[n+1] = f - C v* - K x*,
// then x[n+1] = x* + (T^2/4) a[n+1], v[n+1] = v* + (T/2) a[n+1]. The system matrix
// S = M + (T/2) C + (T^2/4) K is symmetric positive definite (M > 0, C, K >= 0); it is factored once at
// init (sparse LDLT, sparse_ldlt.hpp) and each step is one force evaluation and two triangular solves.
// External force: the force applied for this step is held over it (zero-order hold), so both ends of
// the step see it: a[n] is re-evaluated from the equation of motion at t_n with the new force,
// a[n] <- a[n] + M^-1 (f_new - f_old) (M is diagonal, so this is exact and cheap). The impulse over the
// step is then exactly T f.
// Properties (physics.md section 3): unconditionally stable; for linear undamped links the energy
// 1/2 v'Mv + 1/2 x'Kx is conserved exactly (the update is a Cayley transform, orthogonal in the energy
// norm); an oscillator's frequency is warped to (2/T) atan(omega0 T / 2).
// Net force: sum_i m_i (v_i[n+1] - v_i[n]) / T = sum_i m_i (a_i[n] + a_i[n+1]) / 2.

#include <vector>

#include "engine/core/integrators/network_arrays.hpp"
#include "engine/core/integrators/sparse_ldlt.hpp"

namespace ameoto {

class Trapezoidal {
public:
    void init(const NetworkArrays& net, double time_step_s);
    double step(const NetworkArrays& net, const double* ext);
    void reset();
    bool finite() const;
    double position(std::size_t i) const { return x_[i]; }
    double velocity(std::size_t i) const { return v_[i]; }
    double energy(const NetworkArrays& net) const { return net.energy(x_.data(), v_.data()); }
    const SparseLdlt& factor() const { return solver_; }

private:
    std::vector<double> x_, v_, a_, previous_ext_, x_star_, v_star_, rhs_, a_next_;
    SparseLdlt solver_;
    double dt_ = 0.0;
};

}  // namespace ameoto
