// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/trapezoidal.hpp"

#include <algorithm>
#include <cmath>

namespace ameoto {

void Trapezoidal::init(const NetworkArrays& net, double time_step_s) {
    const std::size_t n = net.mass_count();
    for (auto* v : {&x_, &v_, &a_, &previous_ext_, &x_star_, &v_star_, &rhs_, &a_next_}) v->assign(n, 0.0);
    dt_ = time_step_s;
    // S = M + (T/2) C + (T^2/4) K (see header).
    Eigen::SparseMatrix<double> s = (0.5 * dt_) * net.damping_matrix() + (0.25 * dt_ * dt_) * net.stiffness_matrix();
    for (std::size_t i = 0; i < n; ++i) s.coeffRef(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) += net.mass(i);
    solver_.factor(s);
}

namespace {

// Restrict parameters so the mass loops vectorise (explicit_verlet.cpp explains).
// a[n] at t_n with this step's force (a += M^-1 (f - f_old)), then the predictors x*, v*.
void predict(std::size_t n, const double* __restrict x, const double* __restrict v, double* __restrict a,
             double* __restrict f_old, const double* __restrict ext, const double* __restrict inv_m, double t,
             double* __restrict xs, double* __restrict vs) {
    const double half_t = 0.5 * t, quarter_t2 = 0.25 * t * t;
    for (std::size_t i = 0; i < n; ++i) {
        a[i] += (ext[i] - f_old[i]) * inv_m[i];
        f_old[i] = ext[i];
        xs[i] = x[i] + t * v[i] + quarter_t2 * a[i];
        vs[i] = v[i] + half_t * a[i];
    }
}

// x = x* + (T^2/4) a[n+1], v = v* + (T/2) a[n+1]; returns sum m (a[n] + a[n+1]) / 2.
double correct(std::size_t n, double* __restrict x, double* __restrict v, double* __restrict a,
               const double* __restrict a_next, const double* __restrict xs, const double* __restrict vs,
               const double* __restrict m, double t) {
    const double half_t = 0.5 * t, quarter_t2 = 0.25 * t * t;
    double momentum_change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = xs[i] + quarter_t2 * a_next[i];
        v[i] = vs[i] + half_t * a_next[i];
        momentum_change += m[i] * (a[i] + a_next[i]);
        a[i] = a_next[i];
    }
    return 0.5 * momentum_change;
}

}  // namespace

double Trapezoidal::step(const NetworkArrays& net, const double* ext) {
    const std::size_t n = x_.size();
    predict(n, x_.data(), v_.data(), a_.data(), previous_ext_.data(), ext, net.inverse_mass.data(), dt_, x_star_.data(),
            v_star_.data());
    net.forces(x_star_.data(), v_star_.data(), ext, rhs_.data());
    solver_.solve(rhs_.data(), a_next_.data());
    return correct(n, x_.data(), v_.data(), a_.data(), a_next_.data(), x_star_.data(), v_star_.data(), net.mass_kg.data(), dt_);
}

void Trapezoidal::reset() {
    for (auto* v : {&x_, &v_, &a_, &previous_ext_}) std::fill(v->begin(), v->end(), 0.0);
}

bool Trapezoidal::finite() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) sum += x_[i] + v_[i] + a_[i];
    return std::isfinite(sum);
}

}  // namespace ameoto
