// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D's AVX2 link pass for a body whose links are all cohesive with one set of parameters (a drop;
// body3d.hpp, "Vectorisation", 2.): four links at a time, dense (every link) or sparse (the candidates
// that body3d_sparse_links.cpp lists), each link's bond, core and break as lane masks; a link that breaks
// is recorded here as a LinkBreak event. The scalar reference it must match to the bit is
// uniform_cohesive_links(), body3d_links_scalar.cpp.
// Threads: the render (audio) thread, inside Body3D::step(); never allocates, frees, locks or blocks.
#include <cstdint>

#include "engine/core/body3d.hpp"
#include "engine/core/body3d_avx2.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace ameoto::body3d_avx2 {
namespace {

// 2. The uniform cohesive pass, four links per group. Per lane exactly the scalar pass's arithmetic
// (uniform_cohesive_links()), its branches turned into lane masks. A link's force is s u on a and -s u
// on b; s = 0 or a skipped link (broken, core not touching) adds nothing. Two ways to add them, both in
// link order per mass (so the scalar pass's sums):
//   dense (at least a quarter of the links bonded): links l .. l + 3 at a time; each writes +t = s u
//     and -t to `contribution`, -0.0 for nothing (x + -0 = x for every x), and update() adds them
//     per mass through the slot lists;
//   sparse (most links broken): the candidate links (body3d_sparse_links.cpp), four at a time; the acting
//     ones are added at once to the force accumulator, lane after lane, as the scalar pass does.
// Adds the elastic terms to elastic2 in link order.

template <bool Dense, int Count>
AMEOTO_INLINE void add_link_forces(const StepView& s, const LaneLinks& g, int live, const v4d& tx, const v4d& ty,
                                   const v4d& tz) {
    if constexpr (Dense) {
        // Dense groups are consecutive links: entries 2 l[0] ... are one block.
        const v4d minus_zero = splat(-0.0);
        v4d p0, p1, p2, p3, m0, m1, m2, m3;
        if (live == (1 << Count) - 1) [[likely]] {
            columns_to_rows(tx, ty, tz, p0, p1, p2, p3);
            m0 = -p0;   // exact negation
            m1 = -p1;
            m2 = -p2;
            m3 = -p3;
        } else {
            const v4m on = {-std::int64_t{(live & 1) != 0}, -std::int64_t{(live & 2) != 0},
                            -std::int64_t{(live & 4) != 0}, -std::int64_t{(live & 8) != 0}};
            columns_to_rows(on ? tx : minus_zero, on ? ty : minus_zero, on ? tz : minus_zero, p0, p1, p2, p3);
            columns_to_rows(on ? -tx : minus_zero, on ? -ty : minus_zero, on ? -tz : minus_zero, m0, m1, m2, m3);
        }
        double* out = s.contribution + 8 * g.l[0];
        store4(out, p0);
        store4(out + 4, m0);
        if (Count > 1) store4(out + 8, p1);
        if (Count > 1) store4(out + 12, m1);
        if (Count > 2) store4(out + 16, p2);
        if (Count > 2) store4(out + 20, m2);
        if (Count > 3) store4(out + 24, p3);
        if (Count > 3) store4(out + 28, m3);
    } else {
        for (int k = 0; k < Count; ++k) {
            if (!(live & (1 << k))) continue;
            const auto a = static_cast<std::size_t>(s.la[g.l[k]]), b = static_cast<std::size_t>(s.lb[g.l[k]]);
            s.fx[a] += tx[k];
            s.fy[a] += ty[k];
            s.fz[a] += tz[k];
            s.fx[b] -= tx[k];
            s.fy[b] -= ty[k];
            s.fz[b] -= tz[k];
        }
    }
}

template <bool Dense, int Count>
AMEOTO_INLINE void link_group(const StepView& s, const LaneLinks& g, bool consecutive, double& elastic2) {
    constexpr int all = (1 << Count) - 1;   // the valid lanes' bits
    const int gone_lanes = gone_bits<Count>(s, g, consecutive);
    const v4d zero = splat(0.0), minus_zero = splat(-0.0);
    v4d dx, dy, dz;   // d = x_a - x_b
    link_offsets<Count>(s, g, 0, dx, dy, dz);
    const v4d length2 = dx * dx + dy * dy + dz * dz;
    const v4m gone = lane_mask(gone_lanes);
    const v4m skip = gone & (length2 >= splat(s.core_len2));   // a broken bond's core, not touching
    if (gone_lanes == all && (lane_bits(skip) & all) == all) {
        // All broken and apart (much of a shattered drop): the distance test is all.
        if constexpr (Dense) add_link_forces<Dense, Count>(s, g, 0, zero, zero, zero);
        return;
    }
    v4d wx, wy, wz;   // w = v_a - v_b
    link_offsets<Count>(s, g, 4, wx, wy, wz);
    const v4d length = vsqrt(length2);
    const v4d inv_length = length > zero ? splat(1.0) / length : zero;   // L = 0: no axis, no force
    const v4d ux = dx * inv_length, uy = dy * inv_length, uz = dz * inv_length;
    const v4d stretch = length - splat(s.l0);
    const v4d gap = splat(s.core_len) - length;   // the core pushes while gap > 0
    const v4d spring = splat(-s.k) * stretch;
    const v4d axial_speed = wx * ux + wy * uy + wz * uz;
    const v4d bond = spring - splat(s.damping) * axial_speed;
    const v4d e_spring = splat(s.k) * stretch * stretch;
    // The common case: bonded, no core, not breaking, and s = 0.0 + bond != 0 (so s = bond).
    if (gone_lanes == 0 && lane_bits((gap > zero) | (-spring > splat(s.threshold)) | (bond == zero)) == 0) [[likely]] {
        if (s.energy)
            for (int k = 0; k < Count; ++k) elastic2 += e_spring[k];
        add_link_forces<Dense, Count>(s, g, all, bond * ux, bond * uy, bond * uz);
        return;
    }
    const v4m core_on = (gap > zero) & ~skip;
    const v4d s_core = core_on ? splat(s.core_k) * gap : zero;
    const v4m breaking = ~gone & (-spring > splat(s.threshold));   // torn apart: the spring's pull only
    const v4m acting = ~gone & ~breaking;
    const v4d force = acting ? s_core + bond : s_core;
    const v4d e_core = core_on ? splat(s.core_k) * gap * gap : minus_zero;
    const v4d e_bond = acting ? e_spring : minus_zero;
    if (s.energy)
        for (int k = 0; k < Count; ++k) {
            elastic2 += e_core[k];
            elastic2 += e_bond[k];
        }
    const int breaks = lane_bits(breaking) & all;
    for (int k = 0; k < Count; ++k) {
        if (!(breaks & (1 << k))) continue;
        const std::size_t l = g.l[k];
        s.broken[l] = 1;
        ++*s.broken_count;
        if (*s.event_count < s.event_capacity) {
            s.events[(*s.event_count)++] = LinkBreak{static_cast<std::int32_t>(l), s.la[l], s.lb[l], spring[k], s.index};
        } else {
            ++*s.dropped;
        }
    }
    const int live = lane_bits(~skip & (force != zero)) & all;
    add_link_forces<Dense, Count>(s, g, live, force * ux, force * uy, force * uz);
}

// Dense: every link, l .. l + 3 at a time.
AMEOTO_INLINE double dense_links(const StepView& view) {
    const StepView s = view;
    double elastic2 = 0.0;   // twice the elastic energy
    std::size_t l = 0;
    for (; l + 4 <= s.links; l += 4) link_group<true, 4>(s, consecutive_links<4>(l), true, elastic2);
    switch (s.links - l) {
        case 3: link_group<true, 3>(s, consecutive_links<3>(l), true, elastic2); break;
        case 2: link_group<true, 2>(s, consecutive_links<2>(l), true, elastic2); break;
        case 1: link_group<true, 1>(s, consecutive_links<1>(l), true, elastic2); break;
        default: break;
    }
    return elastic2;
}

// Sparse: the candidates, four at a time.
AMEOTO_INLINE double sparse_links(const StepView& view) {
    const StepView s = view;
    double elastic2 = 0.0;
    std::size_t j = 0;
    for (; j + 4 <= s.candidate_count; j += 4) link_group<false, 4>(s, listed_links<4>(s.candidates + j), false, elastic2);
    switch (s.candidate_count - j) {
        case 3: link_group<false, 3>(s, listed_links<3>(s.candidates + j), false, elastic2); break;
        case 2: link_group<false, 2>(s, listed_links<2>(s.candidates + j), false, elastic2); break;
        case 1: link_group<false, 1>(s, listed_links<1>(s.candidates + j), false, elastic2); break;
        default: break;
    }
    return elastic2;
}

}  // namespace

double dense_links_avx2(const StepView& s) { return dense_links(s); }
double sparse_links_avx2(const StepView& s) { return sparse_links(s); }

}  // namespace ameoto::body3d_avx2

#pragma GCC pop_options
