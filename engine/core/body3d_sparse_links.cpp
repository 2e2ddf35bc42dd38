// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D's sparse link pass (body3d.hpp, "Vectorisation", 2.): once most of a drop's links are broken,
// which links the AVX2 pass computes. The candidates (the bonded links and the broken ones near enough
// to touch), full and partial listings, the approach bound that says when to list again, and
// sparse_links_pass(), which lists when due and runs sparse_links_avx2() (body3d_links_avx2.cpp) on the
// candidates. Every link it leaves out is one the scalar reference (uniform_cohesive_links(),
// body3d_links_scalar.cpp) skips, so the bits are the same.
// Threads: the render (audio) thread, inside Body3D::step(); never allocates, frees, locks or blocks
// (the lists live in buffers that finalize() sized).
#include <cmath>
#include <cstdint>

#include "engine/core/body3d.hpp"
#include "engine/core/body3d_avx2.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace ameoto::body3d_avx2 {
namespace {

// The sparse pass's candidates: the bonded links and the broken ones whose masses are closer than
// s.near (core length + margin), in link order; and the positions they were listed at. Returns how many.
// A full listing looks at every link and also keeps, in link order, the bonded links and the broken ones
// closer than s.far (core length + a wider margin: s.near_links); a partial one looks at those only
// (sparse_links_pass() says when a partial one suffices).
template <int Count, bool Full>
AMEOTO_INLINE void list_group(const StepView& s, const LaneLinks& g, std::size_t& count, std::size_t& near_count) {
    const int gone_lanes = gone_bits<Count>(s, g, Full);   // a full listing's groups are consecutive links
    int keep = ~gone_lanes, near = ~gone_lanes;
    if (gone_lanes != 0) {
        v4d dx, dy, dz;
        link_offsets<Count>(s, g, 0, dx, dy, dz);
        const v4d length2 = dx * dx + dy * dy + dz * dz;
        keep |= lane_bits(~(length2 >= splat(s.near * s.near)));   // NaN: kept
        if constexpr (Full) near |= lane_bits(~(length2 >= splat(s.far * s.far)));
    }
    for (int k = 0; k < Count; ++k) {
        if (keep & (1 << k)) s.candidates[count++] = static_cast<std::int32_t>(g.l[k]);
    }
    if constexpr (Full) {
        for (int k = 0; k < Count; ++k) {
            if (near & (1 << k)) s.near_links[near_count++] = static_cast<std::int32_t>(g.l[k]);
        }
    }
}

template <bool Full>
AMEOTO_INLINE std::size_t list_candidates(const StepView& view) {
    const StepView s = view;
    std::size_t count = 0, near_count = 0;
    if constexpr (Full) {
        std::size_t l = 0;
        for (; l + 4 <= s.links; l += 4) list_group<4, true>(s, consecutive_links<4>(l), count, near_count);
        switch (s.links - l) {
            case 3: list_group<3, true>(s, consecutive_links<3>(l), count, near_count); break;
            case 2: list_group<2, true>(s, consecutive_links<2>(l), count, near_count); break;
            case 1: list_group<1, true>(s, consecutive_links<1>(l), count, near_count); break;
            default: break;
        }
        *s.near_link_count = near_count;
    } else {
        const std::size_t links = *s.near_link_count;
        std::size_t j = 0;
        for (; j + 4 <= links; j += 4) list_group<4, false>(s, listed_links<4>(s.near_links + j), count, near_count);
        switch (links - j) {
            case 3: list_group<3, false>(s, listed_links<3>(s.near_links + j), count, near_count); break;
            case 2: list_group<2, false>(s, listed_links<2>(s.near_links + j), count, near_count); break;
            case 1: list_group<1, false>(s, listed_links<1>(s.near_links + j), count, near_count); break;
            default: break;
        }
    }
    __builtin_memcpy(s.listed_x, s.x, s.n * sizeof(double));
    __builtin_memcpy(s.listed_y, s.y, s.n * sizeof(double));
    __builtin_memcpy(s.listed_z, s.z, s.n * sizeof(double));
    return count;
}

// How far any two masses can have moved towards each other since they were listed: the relative
// displacement of a and b is at most the range (max - min over the masses) of the displacements, per
// axis. Returns the squared bound (NaN if a position is not finite).
AMEOTO_INLINE double approach_bound2(const StepView& view) {
    const StepView s = view;
    DisplacementRange4 range;
    range.clear();
    auto take = [&](std::size_t i, int count) {
        range.take(loadn(s.x + i, count) - loadn(s.listed_x + i, count), loadn(s.y + i, count) - loadn(s.listed_y + i, count),
                   loadn(s.z + i, count) - loadn(s.listed_z + i, count));
    };
    std::size_t i = 0;
    for (; i + 4 <= s.n; i += 4) take(i, 4);
    if (i < s.n) take(i, static_cast<int>(s.n - i));   // the tail's empty lanes read 0: a displacement of 0
    return range.bound2();
}

}  // namespace

std::size_t list_candidates_avx2(const StepView& s, bool full) {
    return full ? list_candidates<true>(s) : list_candidates<false>(s);
}
double approach_bound2_avx2(const StepView& s) { return approach_bound2(s); }

}  // namespace ameoto::body3d_avx2

#pragma GCC pop_options

namespace ameoto {

// The sparse pass computes only the candidates: a broken link left out had its masses at least
// core length + near_margin h = 4 h apart (h: rest length) when listed, and the list is made again
// before they can have approached by 2 h (so they stay 2 h clear of the core, far beyond
// rounding): until then the scalar pass skips it too. The bound compares the positions with
// those listed, so it holds whatever moved them (set_position() too). A position not finite:
// listed again, NaN links kept.
// (Margin and bound measured on a shattered 5 mm drop: 8 h and 4 h, listing about every 9 steps,
// cost 1.7 % more per drop in instructions: more candidates far from touching.)
// The bound of the positions now: the last sparse sub-step's update measured it (fused, no pass
// of its own), unless something has moved a mass since (set_position, reset, finalize).
// A partial listing (the links a full one found closer than core length + far_margin h: the
// bonded and the nearby broken ones) suffices while the others are still near_margin h clear of
// the core:
// each listing's bound (the approach since the listing before) adds to far_travel_, which bounds
// the approach since the last full listing (the triangle inequality), and the next listing comes
// before a further near_margin h / 2; so a full listing when far_travel_ passes far_margin h -
// near_margin h, leaving every link left out at least near_margin h / 2 clear of its core, as above.
double Body3D::sparse_links_pass(body3d_avx2::StepView& s) {
    using namespace body3d_avx2;
    bool full = !candidates_valid_;   // invalidated (dense, reset, finalize): list everything
    if (candidates_valid_) {
        const double bound2 = next_bound_fresh_ ? next_bound2_ : approach_bound2_avx2(s);
        if (!(bound2 < 0.25 * near_margin * near_margin * rest_[0] * rest_[0])) {
            candidates_valid_ = false;
            far_travel_ += std::sqrt(bound2);   // NaN: a full listing
            full = !(far_travel_ <= (far_margin - near_margin) * rest_[0]);
        }
    }
    if (!candidates_valid_) {
        candidate_count_ = list_candidates_avx2(s, full);
        if (full) far_travel_ = 0.0;
        candidates_valid_ = true;
    }
    s.candidate_count = candidate_count_;
    return sparse_links_avx2(s);
}

}  // namespace ameoto
