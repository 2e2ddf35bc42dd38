// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/transverse_network.hpp"

#include <cmath>
#include <stdexcept>

namespace ameoto {
namespace {

// The step's impulse energy for the guard (stability.hpp), sum f^2 / m, and the forces cleared, in one
// pass. Restrict parameters so it vectorises (integrators/explicit_verlet.cpp explains).
double take_forces(std::size_t n, double* __restrict f, const double* __restrict inv_m) {
    double s2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        s2 += f[i] * f[i] * inv_m[i];
        f[i] = 0.0;
    }
    return s2;
}

}  // namespace

int TransverseNetwork::add_mass(double mass_kg, double ground_damping) {
    if (!(mass_kg > 0.0) || !std::isfinite(mass_kg)) throw std::invalid_argument("mass must be positive and finite");
    arrays_.mass_kg.push_back(mass_kg);
    arrays_.inverse_mass.push_back(1.0 / mass_kg);
    arrays_.ground_damping.push_back(ground_damping);
    arrays_.anchor_stiffness.push_back(0.0);
    external_.push_back(0.0);
    return mass_count() - 1;
}

void TransverseNetwork::add_link(int a, int b, double stiffness, double damping) {
    if (a == b || a < 0 || b < 0 || a >= mass_count() || b >= mass_count())
        throw std::invalid_argument("link must join two distinct existing masses");
    arrays_.link_a.push_back(a);
    arrays_.link_b.push_back(b);
    arrays_.link_stiffness.push_back(stiffness);
    arrays_.link_damping.push_back(damping);
}

void TransverseNetwork::add_anchor(int a, double stiffness, double damping) {
    arrays_.anchor_stiffness.at(static_cast<std::size_t>(a)) += stiffness;
    arrays_.ground_damping.at(static_cast<std::size_t>(a)) += damping;
}

void TransverseNetwork::finalize(double time_step_s, const NetworkOptions& options) {
    if (!(time_step_s > 0.0) || !std::isfinite(time_step_s)) throw std::invalid_argument("time step must be positive");
    stability_ = assess_stability(arrays_, time_step_s, options.integrator, options.stability);
    if (stability_.refused) throw StabilityError(stability_.message);
    time_step_ = time_step_s;
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: explicit_.init(arrays_, time_step_s, stability_.sub_steps); break;
        case Integrator::symplectic_euler: symplectic_.init(arrays_, time_step_s, stability_.sub_steps); break;
        case Integrator::trapezoidal: trapezoidal_.init(arrays_, time_step_s); break;
        case Integrator::backward_euler: backward_.init(arrays_, time_step_s); break;
        case Integrator::modal: modal_.init(arrays_, time_step_s, options.modal); break;
    }
    guard_.configure(options.guard, time_step_s);
    check_every_ = options.guard.check_every_steps;
    since_check_ = 0;
    std::fill(external_.begin(), external_.end(), 0.0);
}

double TransverseNetwork::step() {
    const double* ext = external_.data();
    double total = 0.0;
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: total = explicit_.step(arrays_, ext); break;
        case Integrator::symplectic_euler: total = symplectic_.step(arrays_, ext); break;
        case Integrator::trapezoidal: total = trapezoidal_.step(arrays_, ext); break;
        case Integrator::backward_euler: total = backward_.step(arrays_, ext); break;
        case Integrator::modal: total = modal_.step(arrays_, ext); break;
    }
    guard_.inject(time_step_ * std::sqrt(0.5 * take_forces(external_.size(), external_.data(), arrays_.inverse_mass.data())));
    if (check_every_ > 0 && ++since_check_ >= check_every_) {
        since_check_ = 0;
        if (guard()) total = 0.0;
    }
    return total;
}

bool TransverseNetwork::guard() {
    if (!guard_.exceeded(finite(), kinetic_plus_potential_energy())) return false;
    reset();
    guard_.count_reset();
    return true;
}

void TransverseNetwork::reset() {
    explicit_.reset();
    symplectic_.reset();
    trapezoidal_.reset();
    backward_.reset();
    modal_.reset();
    std::fill(external_.begin(), external_.end(), 0.0);
    guard_.clear();
}

bool TransverseNetwork::finite() const {
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.finite();
        case Integrator::symplectic_euler: return symplectic_.finite();
        case Integrator::trapezoidal: return trapezoidal_.finite();
        case Integrator::backward_euler: return backward_.finite();
        case Integrator::modal: return modal_.finite();
    }
    return false;
}

double TransverseNetwork::position(int m) const {
    const auto i = static_cast<std::size_t>(m);
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.position(i);
        case Integrator::symplectic_euler: return symplectic_.position(i);
        case Integrator::trapezoidal: return trapezoidal_.position(i);
        case Integrator::backward_euler: return backward_.position(i);
        case Integrator::modal: return modal_.position(i);
    }
    return 0.0;
}

double TransverseNetwork::velocity(int m) const {
    const auto i = static_cast<std::size_t>(m);
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.velocity(i);
        case Integrator::symplectic_euler: return symplectic_.velocity(i);
        case Integrator::trapezoidal: return trapezoidal_.velocity(i);
        case Integrator::backward_euler: return backward_.velocity(i);
        case Integrator::modal: return modal_.velocity(i);
    }
    return 0.0;
}

namespace {

// The integrator's own inline position(i) / velocity(i) in one loop (vectorised where they allow).
template <class Scheme>
void read_all(const Scheme& scheme, std::size_t n, double* __restrict out, bool velocity) {
    if (velocity) {
        for (std::size_t i = 0; i < n; ++i) out[i] = scheme.velocity(i);
    } else {
        for (std::size_t i = 0; i < n; ++i) out[i] = scheme.position(i);
    }
}

}  // namespace

void TransverseNetwork::positions(double* out) const {
    const std::size_t n = arrays_.mass_count();
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: read_all(explicit_, n, out, false); break;
        case Integrator::symplectic_euler: read_all(symplectic_, n, out, false); break;
        case Integrator::trapezoidal: read_all(trapezoidal_, n, out, false); break;
        case Integrator::backward_euler: read_all(backward_, n, out, false); break;
        case Integrator::modal: read_all(modal_, n, out, false); break;
    }
}

void TransverseNetwork::velocities(double* out) const {
    const std::size_t n = arrays_.mass_count();
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: read_all(explicit_, n, out, true); break;
        case Integrator::symplectic_euler: read_all(symplectic_, n, out, true); break;
        case Integrator::trapezoidal: read_all(trapezoidal_, n, out, true); break;
        case Integrator::backward_euler: read_all(backward_, n, out, true); break;
        case Integrator::modal: read_all(modal_, n, out, true); break;
    }
}

double TransverseNetwork::kinetic_plus_potential_energy() const {
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.energy(arrays_);
        case Integrator::symplectic_euler: return symplectic_.energy(arrays_);
        case Integrator::trapezoidal: return trapezoidal_.energy(arrays_);
        case Integrator::backward_euler: return backward_.energy(arrays_);
        case Integrator::modal: return modal_.energy(arrays_);
    }
    return 0.0;
}

}  // namespace ameoto
