// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D's scalar link passes (body3d.hpp, "Links"): generic_links() for any links (each kind's force,
// contacts' push-only rule, breakable and cohesive links breaking, recorded as LinkBreak events), used
// by both steps when the links are not uniform; and uniform_cohesive_links(), the same cohesive branch
// with its parameters hoisted, the scalar step's pass for a drop and the reference that the AVX2 pass
// (body3d_links_avx2.cpp, body3d_sparse_links.cpp) must match to the bit.
// Threads: the render (audio) thread, inside Body3D::step(); never allocates, frees, locks or blocks.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/core/body3d.hpp"

namespace ameoto {

double Body3D::uniform_cohesive_links(int index) {
    const std::size_t links = link_a_.size();
    const double* __restrict x = x_.data();
    const double* __restrict y = y_.data();
    const double* __restrict z = z_.data();
    const double* __restrict vx = vx_.data();
    const double* __restrict vy = vy_.data();
    const double* __restrict vz = vz_.data();
    double* __restrict fx = fx_.data();
    double* __restrict fy = fy_.data();
    double* __restrict fz = fz_.data();
    const std::int32_t* __restrict la = link_a_.data();
    const std::int32_t* __restrict lb = link_b_.data();
    std::uint8_t* __restrict broken = broken_.data();
    const double k = stiffness_[0], damping = damping_[0], l0 = rest_[0], threshold = break_force_[0];
    const double core_len = core_length_[0], core_k = core_stiffness_[0];
    double elastic2 = 0.0;
    // The cohesive branch of generic_links(), with the parameters hoisted.
    for (std::size_t l = 0; l < links; ++l) {
        const bool gone = broken[l] != 0;
        const auto a = static_cast<std::size_t>(la[l]);
        const auto b = static_cast<std::size_t>(lb[l]);
        const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const double length2 = dx * dx + dy * dy + dz * dz;
        if (gone && length2 >= core_len * core_len) continue;
        const double length = std::sqrt(length2);
        const double inv_length = length > 0.0 ? 1.0 / length : 0.0;
        const double ux = dx * inv_length, uy = dy * inv_length, uz = dz * inv_length;
        const double stretch = length - l0;
        double s = 0.0;
        const double gap = core_len - length;
        if (gap > 0.0) {
            s = core_k * gap;
            elastic2 += core_k * gap * gap;
        }
        if (!gone) {
            const double spring = -k * stretch;
            if (-spring > threshold) {
                broken[l] = 1;
                ++broken_count_;
                if (event_count_ < events_.size()) {
                    events_[event_count_++] = LinkBreak{static_cast<std::int32_t>(l), la[l], lb[l], spring, index};
                } else {
                    ++dropped_breaks_;
                }
            } else {
                const double axial_speed = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
                s += spring - damping * axial_speed;
                elastic2 += k * stretch * stretch;
            }
        }
        if (s == 0.0) continue;
        fx[a] += s * ux;
        fy[a] += s * uy;
        fz[a] += s * uz;
        fx[b] -= s * ux;
        fy[b] -= s * uy;
        fz[b] -= s * uz;
    }
    return elastic2;
}

// 2. Links, any kind (gather/scatter): s along u on a, -s u on b, added to the force accumulator in link
// order. The reference for the uniform pass above. Returns twice the elastic energy.
double Body3D::generic_links(int index) {
    const std::size_t links = link_a_.size();
    const double* __restrict x = x_.data();
    const double* __restrict y = y_.data();
    const double* __restrict z = z_.data();
    const double* __restrict vx = vx_.data();
    const double* __restrict vy = vy_.data();
    const double* __restrict vz = vz_.data();
    double* __restrict fx = fx_.data();
    double* __restrict fy = fy_.data();
    double* __restrict fz = fz_.data();
    const std::int32_t* __restrict la = link_a_.data();
    const std::int32_t* __restrict lb = link_b_.data();
    const double* __restrict lk = stiffness_.data();
    const double* __restrict lz = damping_.data();
    const double* __restrict l0 = rest_.data();
    const double* __restrict lbreak = break_force_.data();
    const LinkKind* __restrict kind = kind_.data();
    std::uint8_t* __restrict broken = broken_.data();
    const double* __restrict core_len = core_length_.data();
    const double* __restrict core_k = core_stiffness_.data();
    double elastic2 = 0.0;   // twice the elastic energy
    for (std::size_t l = 0; l < links; ++l) {
        const LinkKind type = kind[l];
        const bool gone = broken[l] != 0;
        if (gone && type != LinkKind::cohesive) continue;   // a broken cohesive link keeps its core
        const auto a = static_cast<std::size_t>(la[l]);
        const auto b = static_cast<std::size_t>(lb[l]);
        const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const double length2 = dx * dx + dy * dy + dz * dz;
        if (gone && length2 >= core_len[l] * core_len[l]) continue;   // a broken bond's core, not touching
        const double length = std::sqrt(length2);
        const double inv_length = length > 0.0 ? 1.0 / length : 0.0;   // L = 0: no axis, no force
        const double ux = dx * inv_length, uy = dy * inv_length, uz = dz * inv_length;
        const double stretch = length - l0[l];
        double s = 0.0;
        if (type == LinkKind::cohesive) {
            const double gap = core_len[l] - length;   // the core pushes while gap > 0
            if (gap > 0.0) {
                s = core_k[l] * gap;
                elastic2 += core_k[l] * gap * gap;
            }
            if (!gone) {
                const double spring = -lk[l] * stretch;
                if (-spring > lbreak[l]) {   // torn apart: the spring's pull only (see the header)
                    broken[l] = 1;
                    ++broken_count_;
                    if (event_count_ < events_.size()) {
                        events_[event_count_++] = LinkBreak{static_cast<std::int32_t>(l), la[l], lb[l], spring, index};
                    } else {
                        ++dropped_breaks_;
                    }
                } else {
                    const double axial_speed = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
                    s += spring - lz[l] * axial_speed;
                    elastic2 += lk[l] * stretch * stretch;
                }
            }
            if (s == 0.0) continue;
        } else {
            const double axial_speed = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
            s = -lk[l] * stretch - lz[l] * axial_speed;
            if (type == LinkKind::contact) {
                if (stretch >= 0.0) continue;   // not touching
                s = std::max(s, 0.0);           // push only
            }
            if (std::abs(s) > lbreak[l]) {      // only breakable links have a finite threshold
                broken[l] = 1;
                ++broken_count_;
                if (event_count_ < events_.size()) {
                    events_[event_count_++] = LinkBreak{static_cast<std::int32_t>(l), la[l], lb[l], s, index};
                } else {
                    ++dropped_breaks_;
                }
                continue;
            }
            elastic2 += lk[l] * stretch * stretch;
        }
        fx[a] += s * ux;
        fy[a] += s * uy;
        fz[a] += s * uz;
        fx[b] -= s * ux;
        fy[b] -= s * uy;
        fz[b] -= s * uz;
    }
    return elastic2;
}

}  // namespace ameoto
