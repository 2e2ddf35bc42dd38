#include "engine/core/transverse_network.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {

double StabilityReport::margin() const {
    const double dt = time_step / sub_steps;
    return (omega_max_bound * omega_max_bound * dt * dt + 2.0 * gamma_max_bound * dt) / 4.0;
}

int TransverseNetwork::add_mass(double mass_kg, double ground_damping) {
    if (!(mass_kg > 0.0) || !std::isfinite(mass_kg)) throw std::invalid_argument("mass must be positive and finite");
    position_.push_back(0.0);
    previous_.push_back(0.0);
    inverse_mass_.push_back(1.0 / mass_kg);
    ground_damping_.push_back(ground_damping);
    anchor_stiffness_.push_back(0.0);
    force_.push_back(0.0);
    velocity_.push_back(0.0);
    external_.push_back(0.0);
    return mass_count() - 1;
}

void TransverseNetwork::add_link(int a, int b, double stiffness, double damping) {
    if (a == b || a < 0 || b < 0 || a >= mass_count() || b >= mass_count())
        throw std::invalid_argument("link must join two distinct existing masses");
    link_a_.push_back(a);
    link_b_.push_back(b);
    link_stiffness_.push_back(stiffness);
    link_damping_.push_back(damping);
}

void TransverseNetwork::add_anchor(int a, double stiffness, double damping) {
    anchor_stiffness_.at(static_cast<std::size_t>(a)) += stiffness;
    ground_damping_.at(static_cast<std::size_t>(a)) += damping;
}

void TransverseNetwork::finalize(double time_step_s) {
    // Gershgorin on M^-1 K and M^-1 C: row i is bounded by its diagonal plus its off-diagonal sum,
    // (anchor + 2 * sum of links at i) / m_i. An anchor (or a ground damper) only adds to the diagonal,
    // so it counts once; a link to another mass counts twice.
    const std::size_t n = position_.size();
    std::vector<double> k_sum(anchor_stiffness_), z_sum(ground_damping_);
    for (std::size_t l = 0; l < link_a_.size(); ++l) {
        for (auto m : {link_a_[l], link_b_[l]}) {
            k_sum[static_cast<std::size_t>(m)] += 2.0 * link_stiffness_[l];
            z_sum[static_cast<std::size_t>(m)] += 2.0 * link_damping_[l];
        }
    }
    double omega2 = 0.0, gamma = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        omega2 = std::max(omega2, k_sum[i] * inverse_mass_[i]);
        gamma = std::max(gamma, z_sum[i] * inverse_mass_[i]);
    }
    stability_.omega_max_bound = std::sqrt(omega2);
    stability_.gamma_max_bound = gamma;
    stability_.time_step = time_step_s;
    stability_.sub_steps = 1;
    // Fewest sub-steps with margin < 0.9 (10 % head-room against rounding and the bound's slack).
    while (stability_.margin() >= 0.9) {
        if (stability_.sub_steps >= 4096)
            throw std::invalid_argument("network too stiff: needs more than 4096 sub-steps per sample");
        ++stability_.sub_steps;
    }
    sub_dt_ = time_step_s / stability_.sub_steps;
}

double TransverseNetwork::sub_step(double dt) {
    // Every array is read through a local restrict pointer: the force writes cannot alias them, so the
    // compiler keeps the bases in registers instead of reloading them from `this` after each store.
    const std::size_t n = position_.size();
    double* __restrict x = position_.data();
    double* __restrict xp = previous_.data();
    double* __restrict f = force_.data();
    double* __restrict v = velocity_.data();
    const double* __restrict ext = external_.data();
    const double* __restrict ka = anchor_stiffness_.data();
    const double* __restrict zg = ground_damping_.data();
    const double* __restrict inv_m = inverse_mass_.data();
    const std::int32_t* __restrict la = link_a_.data();
    const std::int32_t* __restrict lb = link_b_.data();
    const double* __restrict lk = link_stiffness_.data();
    const double* __restrict lz = link_damping_.data();
    const double inv_dt = 1.0 / dt;

    // Mass-local forces: external, anchor springs, damping to ground; each velocity computed once.
    for (std::size_t i = 0; i < n; ++i) {
        v[i] = (x[i] - xp[i]) * inv_dt;
        f[i] = ext[i] - ka[i] * x[i] - zg[i] * v[i];
    }

    // Link forces (gather/scatter); equal and opposite, so they cancel in the total.
    const std::size_t links = link_a_.size();
    for (std::size_t l = 0; l < links; ++l) {
        const auto a = static_cast<std::size_t>(la[l]);
        const auto b = static_cast<std::size_t>(lb[l]);
        const double force = -lk[l] * (x[a] - x[b]) - lz[l] * (v[a] - v[b]);
        f[a] += force;
        f[b] -= force;
    }

    // Position Verlet: x[n+1] = 2 x[n] - x[n-1] + T^2 F / m.
    const double dt2 = dt * dt;
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double next = 2.0 * x[i] - xp[i] + dt2 * f[i] * inv_m[i];
        xp[i] = x[i];
        x[i] = next;
        total += f[i];
    }
    return total;
}

double TransverseNetwork::step() {
    double total = 0.0;
    for (int s = 0; s < stability_.sub_steps; ++s) total += sub_step(sub_dt_);
    std::fill(external_.begin(), external_.end(), 0.0);
    return total / stability_.sub_steps;
}

void TransverseNetwork::reset() {
    std::fill(position_.begin(), position_.end(), 0.0);
    std::fill(previous_.begin(), previous_.end(), 0.0);
    std::fill(external_.begin(), external_.end(), 0.0);
}

bool TransverseNetwork::finite() const {
    double sum = 0.0;
    for (double x : position_) sum += x;
    return std::isfinite(sum);
}

double TransverseNetwork::velocity(int m) const {
    const auto i = static_cast<std::size_t>(m);
    return (position_[i] - previous_[i]) / sub_dt_;
}

double TransverseNetwork::kinetic_plus_potential_energy() const {
    double energy = 0.0;
    for (std::size_t i = 0; i < position_.size(); ++i) {
        const double v = (position_[i] - previous_[i]) / sub_dt_;
        energy += 0.5 * v * v / inverse_mass_[i] + 0.5 * anchor_stiffness_[i] * position_[i] * position_[i];
    }
    for (std::size_t l = 0; l < link_a_.size(); ++l) {
        const double s = position_[static_cast<std::size_t>(link_a_[l])] - position_[static_cast<std::size_t>(link_b_[l])];
        energy += 0.5 * link_stiffness_[l] * s * s;
    }
    return energy;
}

}  // namespace ameoto
