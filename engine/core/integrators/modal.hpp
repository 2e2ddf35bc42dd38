// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Modal integration: each normal mode advanced exactly as a two-pole resonator.
//
// Interface: as ExplicitVerlet, init(arrays, T, ModalOptions); plus
//   m.mode_count(), m.mode_omega(k), m.mode_damping_rate(k), m.resonator(k) -> {a1, a2, g}
//   m.decomposition()                       // every mode found (before selection)
//
// Model: with Phi mass-normalised (modal_decomposition.hpp), x = Phi q and each mode obeys
//   q_k'' + 2 s_k q_k' + omega_k^2 q_k = p_k,  p = Phi' f,
// s_k = (alpha + beta omega_k^2) / 2 for Rayleigh damping (exact), otherwise the diagonal of Phi' C Phi.
// Discretisation (impulse invariance): the force applied for a step is the impulse T f at the step's
// start, as in the explicit scheme (its x[n+1] = T^2 f / m is the displacement one step after the
// impulse T f). The state (q, q') is kicked, q' += T p, then advanced by the exact transition over T:
//   q(T)  = e^{-sT} [ (cos wd T + s sin(wd T)/wd) q + (sin(wd T)/wd) q' ]
//   q'(T) = e^{-sT} [ -omega^2 (sin(wd T)/wd) q + (cos wd T - s sin(wd T)/wd) q' ],  wd^2 = omega^2 - s^2
// (cosh/sinh with wd -> i mu when overdamped; the limits sin(wd T)/wd -> T when wd -> 0, so free and
// critically damped modes need no special case). Eliminating q' (Cayley-Hamilton on the 2x2 transition,
// trace 2 e^{-sT} cos wd T, determinant e^{-2sT}) gives exactly the two-pole recursion of physics.md
// section 3:
//   q[n] = 2 e^{-sT} cos(wd T) q[n-1] - e^{-2sT} q[n-2] + g p[n],   g = T e^{-sT} sin(wd T) / wd,
// whose impulse response g e^{-s n T} sin(wd (n+1) T) / sin(wd T) = T h((n+1) T) is the continuous mode's
// impulse response h(t) = e^{-st} sin(wd t) / wd times the impulse, sampled: exact at any T (above
// Nyquist a mode aliases, but its samples are still exact). The velocity is carried only because the net
// force needs it.
// Net force: the change of momentum over the step over T, sum_k w_k (q_k'[n+1] - q_k'[n]) / T with
// w_k = sum_i m_i phi_ik: the same quantity the other integrators return. Positions x_i = sum_k phi_ik q_k
// are formed only when asked (position(i)).
// Mode selection (ModalOptions): modes above max_frequency_hz are dropped, then modes whose net-force
// weight |w_k| is below min_net_force_weight * max |w| (the renderer hears a panel only through its net
// force, so such modes are inaudible there: e.g. the antisymmetric modes of a symmetric panel, w_k = 0),
// then only the lowest max_modes are kept. A dropped mode neither moves nor radiates. Valid only while
// the body is linear (no broken links, no contacts; physics.md section 3).
// Cost per step: O(modes) plus O(modes) per mass that received a force.

#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/integrators/network_arrays.hpp"
#include "engine/core/modal_decomposition.hpp"

namespace ameoto {

struct ModalOptions {
    double max_frequency_hz = std::numeric_limits<double>::infinity();
    int max_modes = 0;                   // 0: no limit
    double min_net_force_weight = 0.0;   // relative to the largest |w_k|; 0 keeps every mode
    bool operator==(const ModalOptions&) const = default;
};

struct Resonator {
    double a1 = 0.0, a2 = 0.0, g = 0.0;  // q[n] = a1 q[n-1] + a2 q[n-2] + g p[n]
};

class Modal {
public:
    void init(const NetworkArrays& net, double time_step_s, const ModalOptions& options);
    double step(const NetworkArrays& net, const double* ext);
    void reset();
    bool finite() const;
    double position(std::size_t i) const { return shapes_.row(static_cast<Eigen::Index>(i)).dot(q_); }
    double velocity(std::size_t i) const { return shapes_.row(static_cast<Eigen::Index>(i)).dot(qd_); }
    // 1/2 sum_k (q_k'^2 + omega_k^2 q_k^2): the body's energy when no mode is dropped.
    double energy(const NetworkArrays& net) const;

    int mode_count() const { return static_cast<int>(omega_.size()); }
    double mode_omega(int k) const { return omega_[k]; }
    double mode_damping_rate(int k) const { return rate_[k]; }
    Resonator resonator(int k) const;
    const ModalDecomposition& decomposition() const { return all_; }

private:
    ModalDecomposition all_;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> shapes_;   // masses x kept modes
    Eigen::VectorXd omega_, rate_, weight_, t11_, t12_, t21_, t22_, q_, qd_, p_;
    double dt_ = 0.0;
};

}  // namespace ameoto
