// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/explicit_verlet.hpp"

#include <algorithm>
#include <cmath>

namespace ameoto {

void ExplicitVerlet::init(const NetworkArrays& net, double output_step_s, int sub_steps) {
    const std::size_t n = net.mass_count();
    x_.assign(n, 0.0);
    previous_.assign(n, 0.0);
    force_.assign(n, 0.0);
    velocity_.assign(n, 0.0);
    scratch_.assign(n, 0.0);
    sub_steps_ = std::max(1, sub_steps);
    dt_ = output_step_s / sub_steps_;
    inverse_dt_ = 1.0 / dt_;
}

namespace {

// The kernels take their arrays as restrict-qualified parameters: GCC honours restrict on parameters (also
// after inlining) but not on local pointers, and without it the mass loops would need more run-time alias
// checks than it allows (vect-max-version-for-alias-checks) and stay scalar.

// Mass-local forces: external, anchor springs, damping to ground; each velocity computed once.
void mass_forces(std::size_t n, const double* __restrict x, const double* __restrict xp, const double* __restrict ext,
                 const double* __restrict ka, const double* __restrict zg, double inv_dt, double* __restrict v,
                 double* __restrict f) {
    for (std::size_t i = 0; i < n; ++i) {
        v[i] = (x[i] - xp[i]) * inv_dt;
        f[i] = ext[i] - ka[i] * x[i] - zg[i] * v[i];
    }
}

// Link forces (gather/scatter); equal and opposite, so they cancel in the total. Scalar: two links may
// share a mass, so the scatter cannot be vectorised without conflict detection.
void link_forces(std::size_t links, const std::int32_t* __restrict la, const std::int32_t* __restrict lb,
                 const double* __restrict lk, const double* __restrict lz, const double* __restrict x,
                 const double* __restrict v, double* __restrict f) {
    for (std::size_t l = 0; l < links; ++l) {
        const auto a = static_cast<std::size_t>(la[l]);
        const auto b = static_cast<std::size_t>(lb[l]);
        const double force = -lk[l] * (x[a] - x[b]) - lz[l] * (v[a] - v[b]);
        f[a] += force;
        f[b] -= force;
    }
}

// Position Verlet: x[n+1] = 2 x[n] - x[n-1] + T^2 F / m; returns the sum of the forces.
double verlet_update(std::size_t n, double* __restrict x, double* __restrict xp, const double* __restrict f,
                     const double* __restrict inv_m, double dt2) {
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double next = 2.0 * x[i] - xp[i] + dt2 * f[i] * inv_m[i];
        xp[i] = x[i];
        x[i] = next;
        total += f[i];
    }
    return total;
}

}  // namespace

double ExplicitVerlet::sub_step(const NetworkArrays& net, const double* ext) {
    const std::size_t n = x_.size();
    mass_forces(n, x_.data(), previous_.data(), ext, net.anchor_stiffness.data(), net.ground_damping.data(), inverse_dt_,
                velocity_.data(), force_.data());
    link_forces(net.link_count(), net.link_a.data(), net.link_b.data(), net.link_stiffness.data(), net.link_damping.data(),
                x_.data(), velocity_.data(), force_.data());
    return verlet_update(n, x_.data(), previous_.data(), force_.data(), net.inverse_mass.data(), dt_ * dt_);
}

double ExplicitVerlet::step(const NetworkArrays& net, const double* ext) {
    double total = 0.0;
    for (int s = 0; s < sub_steps_; ++s) total += sub_step(net, ext);
    return total / sub_steps_;
}

void ExplicitVerlet::reset() {
    std::fill(x_.begin(), x_.end(), 0.0);
    std::fill(previous_.begin(), previous_.end(), 0.0);
}

bool ExplicitVerlet::finite() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) sum += x_[i] + previous_[i];
    return std::isfinite(sum);
}

double ExplicitVerlet::energy(const NetworkArrays& net) const {
    for (std::size_t i = 0; i < x_.size(); ++i) scratch_[i] = (x_[i] - previous_[i]) * inverse_dt_;
    return net.energy(x_.data(), scratch_.data());
}

}  // namespace ameoto
