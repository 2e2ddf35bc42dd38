// Body3D's coarse steps: which multiple of the output step a body in flight can take as one
// (body3d.hpp, "Coarse steps"). The step itself is Body3D::step(k) in body3d.cpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/body3d.hpp"

namespace ameoto {

int Body3D::coarse_factor(int max_multiple, double floor_z) {
    if (!finalized_ || max_multiple <= 1 || integrator_ != Integrator::symplectic_euler || external_forces_) return 1;
    if (!(lowest_z_ > floor_z)) return 1;   // unknown (-infinity), NaN, or already at the floor
    max_multiple = std::min(max_multiple, coarse_limit);
    const double g = std::sqrt(dot(gravity_, gravity_));
    const double longest = max_multiple * stability_.time_step;   // the longest step considered, s
    // The speed bound from the last look, with gravity's gain up to the end of the step to come; two
    // masses approach each other at most twice as fast.
    auto speed = [&] { return look_speed_ + g * (since_look_ + longest); };
    if (!coarse_looked_ || !(2.0 * speed() * (since_look_ + longest) < coarse_reach_m_)) {
        const std::size_t n = x_.size();
        double v2_max = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const double v2 = vx_[i] * vx_[i] + vy_[i] * vy_[i] + vz_[i] * vz_[i];
            v2_max = v2 > v2_max ? v2 : v2_max;
        }
        if (!std::isfinite(v2_max)) return 1;
        look_speed_ = 1.5 * std::sqrt(v2_max) + 1.0;
        since_look_ = 0.0;
        coarse_stable_ = stable_coarse_multiple();
        coarse_looked_ = true;
        if (!(2.0 * speed() * longest < coarse_reach_m_)) return 1;   // too fast for a look to hold over one step
    }
    int k = std::min(coarse_stable_, max_multiple);
    // Clear of the floor for the whole step: its lowest mass cannot come down to floor_z within it.
    while (k > 1 && !(lowest_z_ - speed() * (k * stability_.time_step) > floor_z)) --k;
    return k;
}

// Gershgorin over the links that can act (body3d.hpp, "Coarse steps"), as finalize() bounds them all:
// the largest multiple k of the sub-step with margin (omega^2 (k T')^2 + 2 gamma k T') / 4 < 0.9.
int Body3D::stable_coarse_multiple() {
    const std::size_t n = x_.size();
    std::fill(k_sum_.begin(), k_sum_.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
    std::fill(z_sum_.begin(), z_sum_.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
    if (uniform_cohesive_) {
        // A drop: every link cohesive with one set of values (finalize()); the same sums, with the
        // parameters read once.
        const double k_bond = stiffness_[0] + core_stiffness_[0], z_bond = damping_[0], k_core = core_stiffness_[0];
        const double limit = core_length_[0] + coarse_reach_m_, limit2 = limit * limit;
        for (std::size_t l = 0; l < link_a_.size(); ++l) {
            const auto a = static_cast<std::size_t>(link_a_[l]), b = static_cast<std::size_t>(link_b_[l]);
            const double share = (fixed_[a] || fixed_[b]) ? 1.0 : 2.0;
            if (!broken_[l]) {
                k_sum_[a] += share * k_bond;
                k_sum_[b] += share * k_bond;
                z_sum_[a] += share * z_bond;
                z_sum_[b] += share * z_bond;
            } else if (k_core > 0.0) {
                const double dx = x_[a] - x_[b], dy = y_[a] - y_[b], dz = z_[a] - z_[b];
                if (!(dx * dx + dy * dy + dz * dz >= limit2)) {   // NaN: counted
                    k_sum_[a] += share * k_core;
                    k_sum_[b] += share * k_core;
                }
            }
        }
    }
    for (std::size_t l = 0; l < link_a_.size() && !uniform_cohesive_; ++l) {
        const auto a = static_cast<std::size_t>(link_a_[l]), b = static_cast<std::size_t>(link_b_[l]);
        double k = 0.0, z = 0.0;
        // The distance to touching for a broken cohesive link's core or a contact: counted if within reach.
        auto within = [&](double length) {
            const double dx = x_[a] - x_[b], dy = y_[a] - y_[b], dz = z_[a] - z_[b];
            const double limit = length + coarse_reach_m_;
            return !(dx * dx + dy * dy + dz * dz >= limit * limit);   // NaN: counted
        };
        switch (kind_[l]) {
            case LinkKind::spring:
                k = stiffness_[l];
                z = damping_[l];
                break;
            case LinkKind::breakable:
                if (!broken_[l]) {
                    k = stiffness_[l];
                    z = damping_[l];
                }
                break;
            case LinkKind::cohesive:
                if (!broken_[l]) {
                    k = stiffness_[l] + core_stiffness_[l];
                    z = damping_[l];
                } else if (core_stiffness_[l] > 0.0 && within(core_length_[l])) {
                    k = core_stiffness_[l];
                }
                break;
            case LinkKind::contact:
                if (within(rest_[l])) {
                    k = stiffness_[l];
                    z = damping_[l];
                }
                break;
        }
        if (k == 0.0 && z == 0.0) continue;
        const double share = (fixed_[a] || fixed_[b]) ? 1.0 : 2.0;
        k_sum_[a] += share * k;
        k_sum_[b] += share * k;
        z_sum_[a] += share * z;
        z_sum_[b] += share * z;
    }
    double omega2 = 0.0, gamma = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (fixed_[i]) continue;
        const double drag = linear_drag_[i] + 2.0 * quadratic_drag_[i] * speed_bound_;
        omega2 = std::max(omega2, k_sum_[i] * inv_mass_[i]);
        gamma = std::max(gamma, (z_sum_[i] + drag) * inv_mass_[i]);
    }
    int k = 1;
    while (k < coarse_limit) {
        const double t = (k + 1) * sub_dt_;
        if (!((omega2 * t * t + 2.0 * gamma * t) / 4.0 < 0.9)) break;
        ++k;
    }
    return k;
}

}  // namespace ameoto
