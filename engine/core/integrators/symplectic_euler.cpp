// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/symplectic_euler.hpp"

#include <algorithm>
#include <cmath>

namespace ameoto {

void SymplecticEuler::init(const NetworkArrays& net, double output_step_s, int sub_steps) {
    const std::size_t n = net.mass_count();
    x_.assign(n, 0.0);
    v_.assign(n, 0.0);
    force_.assign(n, 0.0);
    sub_steps_ = std::max(1, sub_steps);
    dt_ = output_step_s / sub_steps_;
}

namespace {

// v += T F / m; x += T v; returns the sum of the forces. Restrict parameters: see explicit_verlet.cpp.
double euler_update(std::size_t n, double* __restrict x, double* __restrict v, const double* __restrict f,
                    const double* __restrict inv_m, double dt) {
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        v[i] += dt * f[i] * inv_m[i];
        x[i] += dt * v[i];
        total += f[i];
    }
    return total;
}

}  // namespace

double SymplecticEuler::step(const NetworkArrays& net, const double* ext) {
    double total = 0.0;
    for (int s = 0; s < sub_steps_; ++s) {
        net.forces(x_.data(), v_.data(), ext, force_.data());
        total += euler_update(x_.size(), x_.data(), v_.data(), force_.data(), net.inverse_mass.data(), dt_);
    }
    return total / sub_steps_;
}

void SymplecticEuler::reset() {
    std::fill(x_.begin(), x_.end(), 0.0);
    std::fill(v_.begin(), v_.end(), 0.0);
}

bool SymplecticEuler::finite() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) sum += x_[i] + v_[i];
    return std::isfinite(sum);
}

}  // namespace ameoto
