// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D's scalar sub-step (body3d.hpp, "Vectorisation"): 1. velocities and mass-local forces, 2. the
// link pass (body3d_links_scalar.cpp), 3. the update, one mass at a time. The reference: the AVX2
// kernels (body3d_step_avx2.cpp) must give its bits, and it is the code on a CPU without AVX2, for a
// body under 16 masses, or after set_portable_kernels(true).
// Threads: the render (audio) thread, inside Body3D::step(); never allocates, frees, locks or blocks.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/core/body3d.hpp"

namespace ameoto {

// The scalar step: the reference, and the code on a CPU without AVX2.
void Body3D::sub_step_baseline(int index) {
    // Local restrict pointers (as in transverse_network.cpp): the force stores cannot alias the
    // positions, so the compiler keeps them in registers. (The loops stay scalar: their sums keep the
    // scalar order; sub_step_avx2() vectorises them.)
    const std::size_t n = x_.size();
    double* __restrict x = x_.data();
    double* __restrict y = y_.data();
    double* __restrict z = z_.data();
    double* __restrict px = px_.data();
    double* __restrict py = py_.data();
    double* __restrict pz = pz_.data();
    double* __restrict vx = vx_.data();
    double* __restrict vy = vy_.data();
    double* __restrict vz = vz_.data();
    double* __restrict fx = fx_.data();
    double* __restrict fy = fy_.data();
    double* __restrict fz = fz_.data();
    const double* __restrict ex = ex_.data();
    const double* __restrict ey = ey_.data();
    const double* __restrict ez = ez_.data();
    const double* __restrict m = mass_.data();
    const double* __restrict inv_m = inv_mass_.data();
    const double* __restrict lin = linear_drag_.data();
    const double* __restrict quad = quadratic_drag_.data();
    const double dt = sub_dt_ * dt_scale_, inv_dt = 1.0 / dt;   // x 1.0 (exact) but in a coarse step
    const bool cordis = integrator_ == Integrator::explicit_verlet;

    // 1. Velocities (CORDIS: backward difference) and mass-local forces: external, gravity, drag.
    if (cordis) {
        for (std::size_t i = 0; i < n; ++i) {
            vx[i] = (x[i] - px[i]) * inv_dt;
            vy[i] = (y[i] - py[i]) * inv_dt;
            vz[i] = (z[i] - pz[i]) * inv_dt;
        }
    }
    const double gx = gravity_.x, gy = gravity_.y, gz = gravity_.z;
    const bool energy = energy_limit_ < std::numeric_limits<double>::infinity();
    double kinetic2 = 0.0;   // twice the kinetic energy
    for (std::size_t i = 0; i < n; ++i) {
        const double v2 = vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i];
        const double drag = lin[i] + quad[i] * std::sqrt(v2);   // -c v - b |v| v = -(c + b |v|) v
        fx[i] = ex[i] + m[i] * gx - drag * vx[i];
        fy[i] = ey[i] + m[i] * gy - drag * vy[i];
        fz[i] = ez[i] + m[i] * gz - drag * vz[i];
        if (energy) kinetic2 += m[i] * v2;
    }

    // 2. Links: the uniform cohesive pass (a drop) or any links. (Their elastic energy is summed
    // whatever the limit: the scalar step is the reference, and its cost matters less.)
    const double elastic2 = uniform_cohesive_ ? uniform_cohesive_links(index) : generic_links(index);
    last_energy_ = energy ? 0.5 * (kinetic2 + elastic2) : 0.0;

    // 3. Update. Fixed points have 1/m = 0 and zero velocity, so both schemes leave them in place.
    // The coordinates' sum for the guard in four partial sums, sum[i % 4] (the AVX2 step's lanes).
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    double lowest = std::numeric_limits<double>::infinity();
    if (cordis) {
        // Position Verlet: x[n+1] = 2 x[n] - x[n-1] + T^2 F / m.
        const double dt2 = dt * dt;
        for (std::size_t i = 0; i < n; ++i) {
            const double nx = 2.0 * x[i] - px[i] + dt2 * fx[i] * inv_m[i];
            const double ny = 2.0 * y[i] - py[i] + dt2 * fy[i] * inv_m[i];
            const double nz = 2.0 * z[i] - pz[i] + dt2 * fz[i] * inv_m[i];
            px[i] = x[i];
            py[i] = y[i];
            pz[i] = z[i];
            x[i] = nx;
            y[i] = ny;
            z[i] = nz;
            sum[i % 4] += nx + ny + nz;
            lowest = std::min(lowest, nz);
        }
    } else {
        // Symplectic Euler: v += T F / m, then x += T v with the new v.
        for (std::size_t i = 0; i < n; ++i) {
            vx[i] += dt * fx[i] * inv_m[i];
            vy[i] += dt * fy[i] * inv_m[i];
            vz[i] += dt * fz[i] * inv_m[i];
            px[i] = x[i];
            py[i] = y[i];
            pz[i] = z[i];
            x[i] += dt * vx[i];
            y[i] += dt * vy[i];
            z[i] += dt * vz[i];
            sum[i % 4] += x[i] + y[i] + z[i];
            lowest = std::min(lowest, z[i]);
        }
    }
    last_position_sum_ = ((sum[0] + sum[1]) + sum[2]) + sum[3];
    lowest_z_ = lowest;
}

}  // namespace ameoto
