// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D's AVX2 sub-step (body3d.hpp, "Vectorisation"): the per-mass kernels, 1. velocities and
// mass-local forces (forces()) and 3. the update (update()), four masses at a time, and
// sub_step_avx2(), which fills the StepView (body3d_avx2.hpp) and runs forces(), the links
// (generic_links() in body3d_links_scalar.cpp; dense_links() in body3d_links_avx2.cpp; the sparse pass,
// body3d_sparse_links.cpp), update(). The scalar reference these kernels must match to the bit is
// sub_step_baseline(), body3d_step_scalar.cpp.
// Threads: the render (audio) thread, inside Body3D::step(); never allocates, frees, locks or blocks.
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/core/body3d.hpp"
#include "engine/core/body3d_avx2.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace ameoto::body3d_avx2 {
namespace {

double* align64(double* p) {
    const auto u = reinterpret_cast<std::uintptr_t>(p);
    return reinterpret_cast<double*>((u + 63) & ~std::uintptr_t{63});
}

// 1. Velocities (CORDIS: backward difference) and mass-local forces: external, gravity, drag; for the
// uniform pass also the mirror (position and velocity as one 64-byte row per mass: a link reads each
// end with two loads). Adds m v^2 to kinetic2 in mass order.
// External: apply_force() was called this step (s.ex set). Otherwise every external force is +0.0 and
// +0.0 stands in for its load (0.0 + m g is still added, as the scalar step adds ex = +0.0: the same bits,
// -0.0 included), which frees three of the loop's many pointers.
template <int Count, bool External>
AMEOTO_INLINE void forces_group(const StepView& s, std::size_t i, double& kinetic2) {
    v4d vx, vy, vz;
    if (s.cordis) {
        const v4d inv_dt = splat(s.inv_dt);
        vx = (loadn(s.x + i, Count) - loadn(s.px + i, Count)) * inv_dt;
        vy = (loadn(s.y + i, Count) - loadn(s.py + i, Count)) * inv_dt;
        vz = (loadn(s.z + i, Count) - loadn(s.pz + i, Count)) * inv_dt;
        storen(s.vx + i, vx, Count);
        storen(s.vy + i, vy, Count);
        storen(s.vz + i, vz, Count);
    } else {
        vx = loadn(s.vx + i, Count);
        vy = loadn(s.vy + i, Count);
        vz = loadn(s.vz + i, Count);
    }
    const v4d v2 = vx * vx + vy * vy + vz * vz;
    const v4d drag = loadn(s.lin + i, Count) + loadn(s.quad + i, Count) * vsqrt(v2);   // -(c + b |v|) v
    const v4d m = loadn(s.m + i, Count);
    const v4d ex = External ? loadn(s.ex + i, Count) : splat(0.0);
    const v4d ey = External ? loadn(s.ey + i, Count) : splat(0.0);
    const v4d ez = External ? loadn(s.ez + i, Count) : splat(0.0);
    storen(s.fx + i, ex + m * splat(s.gx) - drag * vx, Count);
    storen(s.fy + i, ey + m * splat(s.gy) - drag * vy, Count);
    storen(s.fz + i, ez + m * splat(s.gz) - drag * vz, Count);
    if (s.energy) {
        const v4d mv2 = m * v2;
        for (int k = 0; k < Count; ++k) kinetic2 += mv2[k];
    }
    if (s.mirror) {
        v4d p0, p1, p2, p3, v0, v1, v2, v3;
        columns_to_rows(loadn(s.x + i, Count), loadn(s.y + i, Count), loadn(s.z + i, Count), p0, p1, p2, p3);
        columns_to_rows(vx, vy, vz, v0, v1, v2, v3);
        double* row = s.mirror + 8 * i;
        store4(row, p0);
        store4(row + 4, v0);
        if (Count > 1) store4(row + 8, p1);
        if (Count > 1) store4(row + 12, v1);
        if (Count > 2) store4(row + 16, p2);
        if (Count > 2) store4(row + 20, v2);
        if (Count > 3) store4(row + 24, p3);
        if (Count > 3) store4(row + 28, v3);
    }
}

template <bool External>
AMEOTO_INLINE double forces(const StepView& view) {
    const StepView s = view;
    double kinetic2 = 0.0;   // twice the kinetic energy
    std::size_t i = 0;
    for (; i + 4 <= s.n; i += 4) forces_group<4, External>(s, i, kinetic2);
    switch (s.n - i) {
        case 3: forces_group<3, External>(s, i, kinetic2); break;
        case 2: forces_group<2, External>(s, i, kinetic2); break;
        case 1: forces_group<1, External>(s, i, kinetic2); break;
        default: break;
    }
    return kinetic2;
}

// 3. Update, four masses per group; for the uniform pass first the link forces, added per mass in link
// order. Adds the new coordinates to sum in mass order. Fixed points have 1/m = 0 and zero velocity,
// so both schemes leave them in place.
template <int Count, bool Track>
AMEOTO_INLINE void update_group(const StepView& s, std::size_t i, v4d& sum, v4d& lowest, DisplacementRange4& range) {
    v4d fx = loadn(s.fx + i, Count), fy = loadn(s.fy + i, Count), fz = loadn(s.fz + i, Count);
    if (s.slots) {
        v4d f0, f1, f2, f3;
        columns_to_rows(fx, fy, fz, f0, f1, f2, f3);
        const std::int32_t* slot = s.slots + s.slot_start[i / 4];
        const std::int32_t* const end = s.slots + s.slot_start[i / 4 + 1];
        for (; slot != end; slot += 4) {
            f0 += load4(s.contribution + slot[0]);
            f1 += load4(s.contribution + slot[1]);
            f2 += load4(s.contribution + slot[2]);
            f3 += load4(s.contribution + slot[3]);
        }
        rows_to_columns(f0, f1, f2, f3, fx, fy, fz);
    }
    const v4d inv_m = loadn(s.inv_m + i, Count);
    const v4d x = loadn(s.x + i, Count), y = loadn(s.y + i, Count), z = loadn(s.z + i, Count);
    v4d nx, ny, nz;
    if (s.cordis) {
        // Position Verlet: x[n+1] = 2 x[n] - x[n-1] + T^2 F / m.
        const v4d dt2 = splat(s.dt * s.dt), two = splat(2.0);
        nx = two * x - loadn(s.px + i, Count) + dt2 * fx * inv_m;
        ny = two * y - loadn(s.py + i, Count) + dt2 * fy * inv_m;
        nz = two * z - loadn(s.pz + i, Count) + dt2 * fz * inv_m;
    } else {
        // Symplectic Euler: v += T F / m, then x += T v with the new v.
        const v4d dt = splat(s.dt);
        const v4d vx = loadn(s.vx + i, Count) + dt * fx * inv_m;
        const v4d vy = loadn(s.vy + i, Count) + dt * fy * inv_m;
        const v4d vz = loadn(s.vz + i, Count) + dt * fz * inv_m;
        storen(s.vx + i, vx, Count);
        storen(s.vy + i, vy, Count);
        storen(s.vz + i, vz, Count);
        nx = x + dt * vx;
        ny = y + dt * vy;
        nz = z + dt * vz;
    }
    storen(s.px + i, x, Count);
    storen(s.py + i, y, Count);
    storen(s.pz + i, z, Count);
    storen(s.x + i, nx, Count);
    storen(s.y + i, ny, Count);
    storen(s.z + i, nz, Count);
    // Lane k sums the masses i = k mod 4 (the scalar step's sum[i % 4]); the lanes past Count add
    // 0 + 0 + 0 = +0, which leaves a lane unchanged (a lane starts at +0 and never becomes -0).
    sum += nx + ny + nz;
    // The lowest z (Body3D::lowest_z()): min is exact, so the scalar step's min gives the same value. The
    // lanes past Count hold 0, not a mass: +infinity there.
    if constexpr (Count == 4) {
        lowest = _mm256_min_pd(lowest, nz);
    } else {
        const v4d inf = splat(std::numeric_limits<double>::infinity());
        const v4d tail = {0.0, Count > 1 ? 0.0 : 1.0, Count > 2 ? 0.0 : 1.0, 1.0};   // 1: a lane past Count
        lowest = _mm256_min_pd(lowest, tail != splat(0.0) ? inf : nz);
    }
    // The sparse pass's next approach bound (approach_bound2() on the positions just written; the
    // tail's empty lanes are 0 - 0).
    if constexpr (Track)
        range.template take<false>(nx - loadn(s.listed_x + i, Count), ny - loadn(s.listed_y + i, Count),
                                   nz - loadn(s.listed_z + i, Count));
}

// Returns the coordinates' sum and sets lowest_z (the lowest new z); with Track, also the approach bound
// of the positions written (bound2).
template <bool Track>
AMEOTO_INLINE double update(const StepView& view, double& lowest_z, double& bound2) {
    const StepView s = view;
    v4d sum = splat(0.0);
    v4d lowest = splat(std::numeric_limits<double>::infinity());
    DisplacementRange4 range;
    if constexpr (Track) range.clear();
    std::size_t i = 0;
    for (; i + 4 <= s.n; i += 4) update_group<4, Track>(s, i, sum, lowest, range);
    switch (s.n - i) {
        case 3: update_group<3, Track>(s, i, sum, lowest, range); break;
        case 2: update_group<2, Track>(s, i, sum, lowest, range); break;
        case 1: update_group<1, Track>(s, i, sum, lowest, range); break;
        default: break;
    }
    // A displacement is NaN only if a position written or listed is not finite, and a coordinate that is
    // not finite never becomes finite again (x + T v, 2 x - x[n-1] + ...), so then the sum is not finite
    // either: the sum stands for the NaN mask (fewer registers in the loop).
    const double total = ((sum[0] + sum[1]) + sum[2]) + sum[3];
    if constexpr (Track) bound2 = std::isfinite(total) ? range.bound2() : std::numeric_limits<double>::quiet_NaN();
    lowest_z = std::min(std::min(lowest[0], lowest[1]), std::min(lowest[2], lowest[3]));
    return total;
}

}  // namespace

double forces_avx2(const StepView& s) { return s.ex ? forces<true>(s) : forces<false>(s); }
double update_avx2(const StepView& s, double& lowest_z) {
    double unused = 0.0;
    return update<false>(s, lowest_z, unused);
}
double update_tracking_avx2(const StepView& s, double& lowest_z, double& bound2) {
    return update<true>(s, lowest_z, bound2);
}

}  // namespace ameoto::body3d_avx2

#pragma GCC pop_options

namespace ameoto {

void Body3D::sub_step_avx2(int index) {
    using namespace body3d_avx2;
    StepView s;
    s.n = x_.size();
    s.links = link_a_.size();
    s.x = x_.data();
    s.y = y_.data();
    s.z = z_.data();
    s.px = px_.data();
    s.py = py_.data();
    s.pz = pz_.data();
    s.vx = vx_.data();
    s.vy = vy_.data();
    s.vz = vz_.data();
    s.fx = fx_.data();
    s.fy = fy_.data();
    s.fz = fz_.data();
    // Null: no apply_force() this step, every external force is +0.0 (forces_group()).
    s.ex = external_forces_ ? ex_.data() : nullptr;
    s.ey = external_forces_ ? ey_.data() : nullptr;
    s.ez = external_forces_ ? ez_.data() : nullptr;
    s.m = mass_.data();
    s.inv_m = inv_mass_.data();
    s.lin = linear_drag_.data();
    s.quad = quadratic_drag_.data();
    s.gx = gravity_.x;
    s.gy = gravity_.y;
    s.gz = gravity_.z;
    s.dt = sub_dt_ * dt_scale_;   // x 1.0 (exact) but in a coarse step
    s.inv_dt = 1.0 / s.dt;
    s.cordis = integrator_ == Integrator::explicit_verlet;
    s.energy = energy_limit_ < std::numeric_limits<double>::infinity();
    s.mirror = nullptr;
    s.contribution = nullptr;
    s.slots = nullptr;
    s.slot_start = nullptr;
    if (uniform_cohesive_) {
        s.mirror = align64(mirror_.data());
        s.contribution = align64(contribution_.data());
        s.ends = link_ends_.data();
        // Dense while at least a quarter of the links are bonded (see dense_links()).
        const bool dense = 4 * (link_a_.size() - broken_count_) >= link_a_.size();
        s.slots = dense ? slots_.data() : nullptr;
        s.candidates = candidates_.data();
        s.listed_x = listed_x_.data();
        s.listed_y = listed_y_.data();
        s.listed_z = listed_z_.data();
        s.near = core_length_[0] + near_margin * rest_[0];
        s.far = core_length_[0] + far_margin * rest_[0];
        s.near_links = near_links_.data();
        s.near_link_count = &near_link_count_;
        s.slot_start = slot_start_.data();
        s.la = link_a_.data();
        s.lb = link_b_.data();
        s.broken = broken_.data();
        s.k = stiffness_[0];
        s.damping = damping_[0];
        s.l0 = rest_[0];
        s.threshold = break_force_[0];
        s.core_len = core_length_[0];
        s.core_len2 = core_length_[0] * core_length_[0];
        s.core_k = core_stiffness_[0];
        s.events = events_.data();
        s.event_capacity = events_.size();
        s.event_count = &event_count_;
        s.dropped = &dropped_breaks_;
        s.broken_count = &broken_count_;
        s.index = index;
    }
    const double kinetic2 = forces_avx2(s);
    double elastic2 = 0.0;
    if (!uniform_cohesive_) {
        elastic2 = generic_links(index);
    } else if (s.slots) {
        candidates_valid_ = false;
        elastic2 = dense_links_avx2(s);
    } else {
        elastic2 = sparse_links_pass(s);   // body3d_sparse_links.cpp
    }
    last_energy_ = s.energy ? 0.5 * (kinetic2 + elastic2) : 0.0;
    const bool sparse = uniform_cohesive_ && !s.slots;
    last_position_sum_ = sparse ? update_tracking_avx2(s, lowest_z_, next_bound2_) : update_avx2(s, lowest_z_);
    next_bound_fresh_ = sparse;
}

}  // namespace ameoto
