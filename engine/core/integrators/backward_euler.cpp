// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/backward_euler.hpp"

#include <algorithm>
#include <cmath>

namespace ameoto {

void BackwardEuler::init(const NetworkArrays& net, double time_step_s) {
    const std::size_t n = net.mass_count();
    for (auto* v : {&x_, &v_, &rhs_, &v_next_}) v->assign(n, 0.0);
    dt_ = time_step_s;
    // M + T C + T^2 K (see header).
    Eigen::SparseMatrix<double> s = dt_ * net.damping_matrix() + (dt_ * dt_) * net.stiffness_matrix();
    for (std::size_t i = 0; i < n; ++i) s.coeffRef(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) += net.mass(i);
    solver_.factor(s);
}

namespace {

// Restrict parameters so the mass loops vectorise (explicit_verlet.cpp explains).
// r = M v + T r (r holds f - K x on entry).
void right_hand_side(std::size_t n, const double* __restrict m, const double* __restrict v, double t, double* __restrict r) {
    for (std::size_t i = 0; i < n; ++i) r[i] = m[i] * v[i] + t * r[i];
}

// v = v[n+1], x += T v[n+1]; returns sum m (v[n+1] - v[n]).
double advance(std::size_t n, double* __restrict x, double* __restrict v, const double* __restrict v_next,
               const double* __restrict m, double t) {
    double momentum_change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        momentum_change += m[i] * (v_next[i] - v[i]);
        v[i] = v_next[i];
        x[i] += t * v_next[i];
    }
    return momentum_change;
}

}  // namespace

double BackwardEuler::step(const NetworkArrays& net, const double* ext) {
    const std::size_t n = x_.size();
    net.forces(x_.data(), nullptr, ext, rhs_.data());   // f - K x[n]
    right_hand_side(n, net.mass_kg.data(), v_.data(), dt_, rhs_.data());
    solver_.solve(rhs_.data(), v_next_.data());
    return advance(n, x_.data(), v_.data(), v_next_.data(), net.mass_kg.data(), dt_) / dt_;
}

void BackwardEuler::reset() {
    std::fill(x_.begin(), x_.end(), 0.0);
    std::fill(v_.begin(), v_.end(), 0.0);
}

bool BackwardEuler::finite() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) sum += x_[i] + v_[i];
    return std::isfinite(sum);
}

}  // namespace ameoto
