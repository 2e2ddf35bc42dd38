// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D between its steps and during one (body3d.hpp): the render-phase setters (integrator, external
// forces, positions, velocities, reset), step() (the sub-steps, the external forces' clearing and the
// runtime guard), the dispatch of each sub-step to the AVX2 or the scalar kernels, and the queries.
// The other parts: body3d_build.cpp (build phase, finalize), body3d_step_scalar.cpp and
// body3d_step_avx2.cpp (a sub-step's per-mass kernels), body3d_links_scalar.cpp and body3d_links_avx2.cpp
// (the link passes, where links break), body3d_sparse_links.cpp (which links the sparse pass computes),
// body3d_coarse.cpp (coarse steps), body3d_drag.cpp (drag coefficients).
// Threads: everything here runs on the render (audio) thread and never allocates, frees, locks or
// blocks; the queries may run on whichever thread owns the body.
#include "engine/core/body3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ameoto {

// ---------------------------------------------------------------------------------------------
// Render phase

bool Body3D::set_integrator(Integrator integrator) {
    if (integrator != Integrator::explicit_verlet && integrator != Integrator::symplectic_euler) return false;
    if (integrator == integrator_) return true;
    // Symplectic Euler reads v as state; CORDIS left only its start-of-sub-step scratch there.
    if (integrator == Integrator::symplectic_euler && sub_dt_ > 0.0) {
        const double inv_dt = 1.0 / sub_dt_;
        for (std::size_t i = 0; i < x_.size(); ++i) {
            vx_[i] = (x_[i] - px_[i]) * inv_dt;
            vy_[i] = (y_[i] - py_[i]) * inv_dt;
            vz_[i] = (z_[i] - pz_[i]) * inv_dt;
        }
    }
    // Symplectic Euler keeps x[n-1] up to date, so the switch to CORDIS needs nothing.
    integrator_ = integrator;
    return true;
}

void Body3D::apply_force(int mass, Vec3 f) {
    const auto i = idx(mass);
    external_forces_ = true;
    ex_[i] += f.x;
    ey_[i] += f.y;
    ez_[i] += f.z;
}

void Body3D::set_position(int mass, Vec3 p) {
    const auto i = idx(mass);
    const Vec3 v = velocity(mass);
    x_[i] = p.x;
    y_[i] = p.y;
    z_[i] = p.z;
    px_[i] = p.x - sub_dt_ * v.x;
    py_[i] = p.y - sub_dt_ * v.y;
    pz_[i] = p.z - sub_dt_ * v.z;
    next_bound_fresh_ = false;   // the sparse pass measures its bound again (sparse_links_pass())
    lowest_z_ = -std::numeric_limits<double>::infinity();   // unknown until the next step
    coarse_looked_ = false;   // coarse_factor() looks at the links again
}

void Body3D::set_velocity(int mass, Vec3 v) {
    const auto i = idx(mass);
    if (fixed_[i]) return;
    vx_[i] = v.x;
    vy_[i] = v.y;
    vz_[i] = v.z;
    px_[i] = x_[i] - sub_dt_ * v.x;
    py_[i] = y_[i] - sub_dt_ * v.y;
    pz_[i] = z_[i] - sub_dt_ * v.z;
}

void Body3D::freeze(int mass, Vec3 at) {
    const auto i = idx(mass);
    if (fixed_[i]) return;
    set_position(mass, at);
    set_velocity(mass, Vec3{});
    inv_mass_[i] = 0.0;
}

void Body3D::reset() {
    // A frozen mass moves again (the same 1 / m as add_mass computed).
    for (std::size_t i = 0; i < mass_.size(); ++i)
        if (!fixed_[i]) inv_mass_[i] = 1.0 / mass_[i];
    std::copy(x0_.begin(), x0_.end(), x_.begin());
    std::copy(y0_.begin(), y0_.end(), y_.begin());
    std::copy(z0_.begin(), z0_.end(), z_.begin());
    std::copy(x0_.begin(), x0_.end(), px_.begin());
    std::copy(y0_.begin(), y0_.end(), py_.begin());
    std::copy(z0_.begin(), z0_.end(), pz_.begin());
    for (auto* a : {&vx_, &vy_, &vz_, &ex_, &ey_, &ez_}) std::fill(a->begin(), a->end(), 0.0);
    std::fill(broken_.begin(), broken_.end(), std::uint8_t{0});
    broken_count_ = 0;
    candidates_valid_ = false;
    next_bound_fresh_ = false;
    event_count_ = 0;
    last_energy_ = 0.0;
    last_position_sum_ = 0.0;
    lowest_z_ = -std::numeric_limits<double>::infinity();
    coarse_looked_ = false;   // coarse_factor() looks at the links again
}

void Body3D::sub_step(int index) {
    if (use_avx2_) {
        sub_step_avx2(index);
    } else {
        sub_step_baseline(index);
    }
}

bool Body3D::step(int time_multiple) {
    event_count_ = 0;
    if (!finalized_) return false;   // built or changed since finalize(): nothing is sized to run
    if (time_multiple > 1 && integrator_ == Integrator::symplectic_euler) {
        // A coarse step (see the header): the same sub-steps with a k times longer step.
        dt_scale_ = static_cast<double>(time_multiple);
        for (int s = 0; s < stability_.sub_steps; ++s) sub_step(s);
        dt_scale_ = 1.0;
        since_look_ += time_multiple * stability_.time_step;
        since_bonds_ += time_multiple * stability_.time_step;
    } else {
        // CORDIS keeps x[n-1], tied to the sub-step: k ordinary steps (their breaks all listed).
        for (int k = 0; k < std::max(time_multiple, 1); ++k)
            for (int s = 0; s < stability_.sub_steps; ++s) sub_step(s);
        since_look_ += std::max(time_multiple, 1) * stability_.time_step;
        since_bonds_ += std::max(time_multiple, 1) * stability_.time_step;
    }
    // Held for this step only. Cleared only if apply_force() was called since the last clearing (collisions
    // touch a drop for a few steps of its life): otherwise they are all +0.0 already.
    if (external_forces_) {
        for (auto* a : {&ex_, &ey_, &ez_}) std::fill(a->begin(), a->end(), 0.0);
        external_forces_ = false;
    }
    // The guard: a NaN or Inf anywhere reaches the position sum (or the energy); the limit catches a
    // blow-up before it overflows.
    if (!std::isfinite(last_position_sum_) || !std::isfinite(last_energy_) || last_energy_ > energy_limit_) {
        reset();
        ++resets_;
        return false;
    }
    return true;
}

// ---------------------------------------------------------------------------------------------
// Queries

Vec3 Body3D::position(int m) const {
    const auto i = idx(m);
    return {x_[i], y_[i], z_[i]};
}

Vec3 Body3D::velocity(int m) const {
    const auto i = idx(m);
    if (integrator_ == Integrator::symplectic_euler || !(sub_dt_ > 0.0)) return {vx_[i], vy_[i], vz_[i]};
    const double inv_dt = 1.0 / sub_dt_;
    return {(x_[i] - px_[i]) * inv_dt, (y_[i] - py_[i]) * inv_dt, (z_[i] - pz_[i]) * inv_dt};
}

double Body3D::total_mass() const {
    double total = 0.0;
    for (double m : mass_) total += m;
    return total;
}

Vec3 Body3D::centre_of_mass() const {
    Vec3 sum{};
    for (std::size_t i = 0; i < x_.size(); ++i) sum = sum + mass_[i] * Vec3{x_[i], y_[i], z_[i]};
    return sum / total_mass();
}

Vec3 Body3D::momentum() const {
    Vec3 p{};
    for (int i = 0; i < mass_count(); ++i) p = p + mass_[idx(i)] * velocity(i);
    return p;
}

double Body3D::kinetic_energy() const {
    double e = 0.0;
    for (int i = 0; i < mass_count(); ++i) {
        const Vec3 v = velocity(i);
        e += 0.5 * mass_[idx(i)] * dot(v, v);
    }
    return e;
}

double Body3D::elastic_energy() const {
    double e = 0.0;
    for (std::size_t l = 0; l < link_a_.size(); ++l) {
        const auto a = idx(link_a_[l]), b = idx(link_b_[l]);
        const double length = norm(Vec3{x_[a] - x_[b], y_[a] - y_[b], z_[a] - z_[b]});
        const double gap = core_length_[l] - length;
        if (gap > 0.0) e += 0.5 * core_stiffness_[l] * gap * gap;   // cohesive cores, bonded or not
        if (broken_[l]) continue;
        const double stretch = length - rest_[l];
        if (kind_[l] == LinkKind::contact && stretch >= 0.0) continue;
        e += 0.5 * stiffness_[l] * stretch * stretch;
    }
    return e;
}

int Body3D::broken_link_count() const {
    int count = 0;
    for (auto b : broken_) count += b;
    return count;
}

}  // namespace ameoto
