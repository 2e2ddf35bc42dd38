// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/modal.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/integrators/mode_decay.hpp"

namespace ameoto {

void Modal::init(const NetworkArrays& net, double time_step_s, const ModalOptions& options) {
    dt_ = time_step_s;
    all_ = decompose_modes(net);
    const Eigen::Index n = all_.omega.size();
    const double w_max = n > 0 ? all_.net_force_weight.cwiseAbs().maxCoeff() : 0.0;
    std::vector<Eigen::Index> keep;
    for (Eigen::Index k = 0; k < n; ++k) {   // ascending frequency
        if (all_.omega[k] / (2.0 * 3.14159265358979323846) > options.max_frequency_hz) continue;
        if (std::abs(all_.net_force_weight[k]) < options.min_net_force_weight * w_max) continue;
        if (options.max_modes > 0 && static_cast<int>(keep.size()) >= options.max_modes) break;
        keep.push_back(k);
    }
    const auto kept = static_cast<Eigen::Index>(keep.size());
    shapes_.resize(n, kept);
    for (auto* v : {&omega_, &rate_, &weight_, &t11_, &t12_, &t21_, &t22_, &q_, &qd_, &p_}) v->setZero(kept);
    for (Eigen::Index j = 0; j < kept; ++j) {
        const Eigen::Index k = keep[static_cast<std::size_t>(j)];
        shapes_.col(j) = all_.shapes.col(k);
        omega_[j] = all_.omega[k];
        rate_[j] = all_.damping_rate[k];
        weight_[j] = all_.net_force_weight[k];
        const ModeDecay dc = mode_decay(omega_[j], rate_[j], dt_);
        t11_[j] = dc.ec + rate_[j] * dc.es;
        t12_[j] = dc.es;
        t21_[j] = -omega_[j] * omega_[j] * dc.es;
        t22_[j] = dc.ec - rate_[j] * dc.es;
    }
}

namespace {

// Restrict parameters so the mode loops vectorise (explicit_verlet.cpp explains).
// p += f * phi_i (one mass's row of the shapes).
void project(std::size_t modes, double f, const double* __restrict row, double* __restrict p) {
    for (std::size_t k = 0; k < modes; ++k) p[k] += f * row[k];
}

// Kick q' += T p, then the exact 2x2 transition; returns sum w (q'[n+1] - q'[n]).
double advance_modes(std::size_t modes, double* __restrict q, double* __restrict qd, const double* __restrict p,
                     const double* __restrict a11, const double* __restrict a12, const double* __restrict a21,
                     const double* __restrict a22, const double* __restrict w, double t) {
    double momentum_change = 0.0;
    for (std::size_t k = 0; k < modes; ++k) {
        const double kicked = qd[k] + t * p[k];
        const double q_next = a11[k] * q[k] + a12[k] * kicked;
        const double qd_next = a21[k] * q[k] + a22[k] * kicked;
        momentum_change += w[k] * (qd_next - qd[k]);
        q[k] = q_next;
        qd[k] = qd_next;
    }
    return momentum_change;
}

}  // namespace

double Modal::step(const NetworkArrays& net, const double* ext) {
    const auto kept = static_cast<std::size_t>(q_.size());
    p_.setZero();
    // p = Phi' f over the masses that received a force (rain hits a few nodes per sample).
    const std::size_t n = net.mass_count();
    for (std::size_t i = 0; i < n; ++i)
        if (ext[i] != 0.0) project(kept, ext[i], shapes_.data() + i * kept, p_.data());
    return advance_modes(kept, q_.data(), qd_.data(), p_.data(), t11_.data(), t12_.data(), t21_.data(), t22_.data(),
                         weight_.data(), dt_) / dt_;
}

void Modal::reset() {
    q_.setZero();
    qd_.setZero();
}

bool Modal::finite() const { return std::isfinite(q_.sum() + qd_.sum()); }

double Modal::energy(const NetworkArrays&) const {
    return 0.5 * (qd_.squaredNorm() + (omega_.array() * q_.array()).square().sum());
}

Resonator Modal::resonator(int k) const {
    const double trace = t11_[k] + t22_[k];
    const double det = t11_[k] * t22_[k] - t12_[k] * t21_[k];
    return {trace, -det, t12_[k] * dt_};
}

}  // namespace ameoto
