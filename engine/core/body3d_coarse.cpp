// SPDX-License-Identifier: GPL-3.0-or-later
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
        look_at_links();
        coarse_looked_ = true;
        if (!(2.0 * speed() * longest < coarse_reach_m_)) return 1;   // too fast for a look to hold over one step
    }
    // The bonds' own cores, checked again once one of them could have closed its gap since the last check.
    if (!bonds_checked_ || !(since_bonds_ + longest < bonds_clear_for_)) check_bonds(longest);
    const double omega2 = bonds_omega2_;
    int k = 1;
    while (k < max_multiple) {
        const double t = (k + 1) * sub_dt_;
        if (!((omega2 * t * t + 2.0 * coarse_gamma_ * t) / 4.0 < 0.9)) break;
        ++k;
    }
    // Clear of the floor for the whole step: its lowest mass cannot come down to floor_z within it.
    while (k > 1 && !(lowest_z_ - speed() * (k * stability_.time_step) > floor_z)) --k;
    return k;
}

// Gershgorin over the links that can act (body3d.hpp, "Coarse steps") until the next look, as
// finalize() bounds them all, except the cores of intact cohesive links: their springs and dampers
// count here, their cores are judged by check_bonds(), and they are listed for it in coarse_bonds_.
// Sets coarse_omega2_ and coarse_gamma_ (the largest over the masses), leaves the per-mass sums in
// k_sum_ and z_sum_, and bond_accel_: how fast a bond's two masses can speed towards each other.
void Body3D::look_at_links() {
    const std::size_t n = x_.size();
    std::fill(k_sum_.begin(), k_sum_.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
    std::fill(z_sum_.begin(), z_sum_.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
    coarse_bonds_.clear();   // within the capacity finalize() gave it (one entry per link)
    bonds_checked_ = false;
    bond_accel_ = 0.0;
    if (uniform_cohesive_) {
        // A drop: every link cohesive with one set of values (finalize()); the same sums, with the
        // parameters read once.
        const double k_bond = stiffness_[0], z_bond = damping_[0], k_core = core_stiffness_[0];
        const double limit = core_length_[0] + coarse_reach_m_, limit2 = limit * limit;
        for (std::size_t l = 0; l < link_a_.size(); ++l) {
            const auto a = static_cast<std::size_t>(link_a_[l]), b = static_cast<std::size_t>(link_b_[l]);
            const double share = (fixed_[a] || fixed_[b]) ? 1.0 : 2.0;
            if (!broken_[l]) {
                k_sum_[a] += share * k_bond;
                k_sum_[b] += share * k_bond;
                z_sum_[a] += share * z_bond;
                z_sum_[b] += share * z_bond;
                if (k_core > 0.0) {
                    coarse_bonds_.push_back(static_cast<std::int32_t>(l));
                    core_extra_[a] += 1.0;   // counts the bonds per mass, for bond_accel_ below
                    core_extra_[b] += 1.0;
                }
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
                if (!broken_[l]) {   // a non-uniform body: the bond and its core, as finalize() counts them
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
    gershgorin_maxima(coarse_omega2_, coarse_gamma_);
    // A bond pulls or pushes each of its masses by at most its break force (beyond it, it breaks; its
    // spring's push before the core engages, k (l0 - l_c), and its damper's are far smaller: 1e-5 N
    // against 1e-4 N in a 5 mm water drop, counted as a second break force). A mass with d bonds:
    // 2 d F / m; two masses approach at up to twice that.
    if (!coarse_bonds_.empty()) {
        const double force = 2.0 * break_force_[0];
        for (std::size_t i = 0; i < n; ++i) {
            if (core_extra_[i] > 0.0) bond_accel_ = std::max(bond_accel_, 2.0 * core_extra_[i] * force * inv_mass_[i]);
            core_extra_[i] = 0.0;
        }
    }
}

// The cores of the bonds listed at the look (coarse_bonds_): a core pushes only once its masses are
// closer than its length, and a bond's two masses move nearly together (their relative speed, from
// the bond's vibration, is a small part of the pieces' flight speed). A bond whose gap G = L - l_c
// could close within the step to come, at 1.5 x its masses' relative speed w now and bond_accel_
// (w t + a t^2 / 2 = G), counts its core; the others are clear for that time t, and the check holds
// until the first of them might not be. Sets bonds_omega2_: the look's bound with the engaged cores.
void Body3D::check_bonds(double step_s) {
    double omega2 = coarse_omega2_, clear_for = std::numeric_limits<double>::infinity();
    std::size_t touched = 0;
    const double a = bond_accel_;
    for (const std::int32_t link : coarse_bonds_) {
        const auto l = static_cast<std::size_t>(link);
        const auto p = static_cast<std::size_t>(link_a_[l]), q = static_cast<std::size_t>(link_b_[l]);
        const double dx = x_[p] - x_[q], dy = y_[p] - y_[q], dz = z_[p] - z_[q];
        const double wx = vx_[p] - vx_[q], wy = vy_[p] - vy_[q], wz = vz_[p] - vz_[q];
        const double gap = std::sqrt(dx * dx + dy * dy + dz * dz) - core_length_[l];
        const double w = 1.5 * std::sqrt(wx * wx + wy * wy + wz * wz);
        // The time to close the gap, 2 G / (w + sqrt(w^2 + 2 a G)) (the root of w t + a t^2 / 2 = G
        // without cancellation); 0 if already closed, or NaN.
        const double t = gap > 0.0 ? 2.0 * gap / (w + std::sqrt(w * w + 2.0 * a * gap)) : 0.0;
        if (t > step_s) {
            clear_for = std::min(clear_for, t);
            continue;
        }
        const double share = (fixed_[p] || fixed_[q]) ? 1.0 : 2.0;
        for (const std::size_t m : {p, q}) {
            if (core_extra_[m] == 0.0) touched_[touched++] = static_cast<std::int32_t>(m);
            core_extra_[m] += share * core_stiffness_[l];
        }
    }
    for (std::size_t i = 0; i < touched; ++i) {
        const auto m = static_cast<std::size_t>(touched_[i]);
        if (!fixed_[m]) omega2 = std::max(omega2, (k_sum_[m] + core_extra_[m]) * inv_mass_[m]);
        core_extra_[m] = 0.0;
    }
    bonds_omega2_ = omega2;
    bonds_clear_for_ = clear_for;
    since_bonds_ = 0.0;
    bonds_checked_ = true;
}

}  // namespace ameoto
