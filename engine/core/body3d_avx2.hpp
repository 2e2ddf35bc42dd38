// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to Body3D's AVX2 kernels (body3d_step_avx2.cpp, body3d_links_avx2.cpp, body3d_sparse_links.cpp;
// included by nothing else): the 4-lane vector type and its helpers, the StepView every kernel reads
// and writes, a group of four links and its gathers, the displacements' range, and the kernels' entry
// points. Everything here is compiled for AVX2 whatever the build's target (the region below) and runs
// only where finalize() found AVX2. Written on 4-lane vectors (GCC vector extensions): lane by lane the
// same IEEE operations in the same order as the scalar reference (body3d_step_scalar.cpp,
// body3d_links_scalar.cpp), so the same bits (body3d.hpp, "Bit identity"). No FMA (AVX2 does not include
// it, and every file that includes this is compiled with -ffp-contract=off, engine/CMakeLists.txt), no
// reassociation (sums across lanes are added lane by lane, in the scalar order).
// Threads: the kernels run on the render (audio) thread inside Body3D::step(); they never allocate,
// free, lock or block.

#include <immintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "engine/core/body3d.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace ameoto::body3d_avx2 {

// ---- the kernels (AVX2 code: called only where finalize() found AVX2) ----
struct StepView;
// body3d_step_avx2.cpp: 1. velocities and mass-local forces (returns twice the kinetic energy, if
// s.energy); 3. the update (returns the coordinates' sum; _tracking: also the sparse pass's next
// approach bound, bound2).
double forces_avx2(const StepView& s);
double update_avx2(const StepView& s, double& lowest_z);
double update_tracking_avx2(const StepView& s, double& lowest_z, double& bound2);
// body3d_links_avx2.cpp: 2. the uniform cohesive link pass, dense or over the candidates (returns twice
// the elastic energy, if s.energy).
double dense_links_avx2(const StepView& s);
double sparse_links_avx2(const StepView& s);
// body3d_sparse_links.cpp: the sparse pass's candidates (returns how many) and the approach bound.
std::size_t list_candidates_avx2(const StepView& s, bool full);
double approach_bound2_avx2(const StepView& s);

// ---- shared by the kernels ----
using v4d = double __attribute__((vector_size(32)));
using v4m = std::int64_t __attribute__((vector_size(32)));   // a lane mask, 0 or -1, as comparisons give

#define AMEOTO_INLINE inline __attribute__((always_inline))

AMEOTO_INLINE v4d load4(const double* p) {
    v4d v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
AMEOTO_INLINE void store4(double* p, const v4d& v) { __builtin_memcpy(p, &v, sizeof v); }
// Lanes past `count` (an array's tail) read as 0 and are not written.
AMEOTO_INLINE v4d loadn(const double* p, int count) {
    if (count == 4) return load4(p);
    v4d v = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < count; ++k) v[k] = p[k];
    return v;
}
AMEOTO_INLINE void storen(double* p, const v4d& v, int count) {
    if (count == 4) return store4(p, v);
    for (int k = 0; k < count; ++k) p[k] = v[k];
}
AMEOTO_INLINE v4d splat(double a) { return v4d{a, a, a, a}; }
AMEOTO_INLINE v4d vsqrt(const v4d& a) { return _mm256_sqrt_pd(a); }

// Rows (x y z w) of four items <-> columns x, y, z (w dropped; w = 0 going back).
AMEOTO_INLINE void rows_to_columns(const v4d& r0, const v4d& r1, const v4d& r2, const v4d& r3, v4d& x, v4d& y,
                                   v4d& z) {
    const v4d t0 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6);   // x0 x1 z0 z1
    const v4d t1 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7);   // y0 y1 w0 w1
    const v4d t2 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6);   // x2 x3 z2 z3
    const v4d t3 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);   // y2 y3 w2 w3
    x = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    y = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    z = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
}
AMEOTO_INLINE void columns_to_rows(const v4d& x, const v4d& y, const v4d& z, v4d& r0, v4d& r1, v4d& r2, v4d& r3) {
    const v4d zero = {0.0, 0.0, 0.0, 0.0};
    const v4d t0 = __builtin_shufflevector(x, y, 0, 4, 2, 6);      // x0 y0 x2 y2
    const v4d t1 = __builtin_shufflevector(x, y, 1, 5, 3, 7);      // x1 y1 x3 y3
    const v4d t2 = __builtin_shufflevector(z, zero, 0, 4, 2, 6);   // z0 0 z2 0
    const v4d t3 = __builtin_shufflevector(z, zero, 1, 5, 3, 7);   // z1 0 z3 0
    r0 = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    r1 = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    r2 = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    r3 = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}

// A lane mask as bits (lane k: bit k).
AMEOTO_INLINE int lane_bits(const v4m& m) { return _mm256_movemask_pd(reinterpret_cast<__m256d>(m)); }

// Everything a sub-step's kernels read and write. Each kernel copies it first: a local copy lives in
// registers, where a reference would be read again after every store of a double.
struct StepView {
    std::size_t n = 0, links = 0;
    double *x, *y, *z, *px, *py, *pz, *vx, *vy, *vz, *fx, *fy, *fz;
    const double *ex, *ey, *ez, *m, *inv_m, *lin, *quad;
    double gx, gy, gz, dt, inv_dt;
    bool cordis;
    bool energy;                    // sum the energies (only for a finite energy limit: the guard)
    // The uniform cohesive pass (null otherwise).
    double* mirror;                 // per mass x y z 0 vx vy vz 0, written by forces()
    double* contribution;           // entry e at 4 e: [2 l] = +t, [2 l + 1] = -t of link l, [2 links] = -0.0
    const std::int32_t* ends;       // per link 8 a, 8 b: its masses' rows in the mirror
    const std::int32_t* slots;      // per group of 4 masses, rows of 4 entries x 4 (one per mass);
                                    // null: the sparse pass
    const std::int32_t* slot_start;
    std::int32_t* candidates;       // the sparse pass's links
    std::size_t candidate_count;
    std::int32_t* near_links;       // the links a partial listing looks at (list_candidates())
    std::size_t* near_link_count;
    double far;                     // ... a full listing leaves out broken links at least this long
    double near;                    // a broken link is listed if its masses are closer than this
    double *listed_x, *listed_y, *listed_z;   // positions when listed
    const std::int32_t *la, *lb;
    std::uint8_t* broken;
    double k, damping, l0, threshold, core_len, core_len2, core_k;
    LinkBreak* events;
    std::size_t event_capacity;
    std::size_t* event_count;
    long* dropped;
    std::size_t* broken_count;
    int index;
};

// A group's links: l[k] for lane k; lanes past Count repeat the last link and are ignored.
struct LaneLinks {
    std::size_t l[4];
};

// d = x_a - x_b of the group's links, as columns.
template <int Count>
AMEOTO_INLINE void link_offsets(const StepView& s, const LaneLinks& g, int row, v4d& x, v4d& y, v4d& z) {
    auto a = [&](int k) { return s.mirror + s.ends[2 * g.l[k]] + row; };
    auto b = [&](int k) { return s.mirror + s.ends[2 * g.l[k] + 1] + row; };
    rows_to_columns(load4(a(0)) - load4(b(0)), load4(a(1)) - load4(b(1)), load4(a(2)) - load4(b(2)),
                    load4(a(3)) - load4(b(3)), x, y, z);
}

template <int Count>
AMEOTO_INLINE int gone_bits(const StepView& s, const LaneLinks& g, bool consecutive) {
    if (Count == 4 && consecutive) {
        std::uint32_t word;   // broken flags are 0 or 1
        __builtin_memcpy(&word, s.broken + g.l[0], sizeof word);
        return static_cast<int>((word & 1u) | (word >> 7 & 2u) | (word >> 14 & 4u) | (word >> 21 & 8u));
    }
    int bits = 0;
    for (int k = 0; k < Count; ++k) bits |= s.broken[g.l[k]] != 0 ? 1 << k : 0;
    return bits;
}

AMEOTO_INLINE v4m lane_mask(int bits) {
    return v4m{-std::int64_t{(bits & 1) != 0}, -std::int64_t{(bits & 2) != 0}, -std::int64_t{(bits & 4) != 0},
               -std::int64_t{(bits & 8) != 0}};
}

template <int Count>
AMEOTO_INLINE LaneLinks consecutive_links(std::size_t first) {
    LaneLinks g;
    for (int k = 0; k < 4; ++k) g.l[k] = first + static_cast<std::size_t>(k < Count ? k : Count - 1);
    return g;
}

template <int Count>
AMEOTO_INLINE LaneLinks listed_links(const std::int32_t* list) {
    LaneLinks g;
    for (int k = 0; k < 4; ++k) g.l[k] = static_cast<std::size_t>(list[k < Count ? k : Count - 1]);
    return g;
}

// The displacements' range, gathered four masses at a time (lanes), by approach_bound2() or, fused
// into the update, by update() for the next sub-step. (Members set by clear(), not by initialisers: an
// implicit constructor would be compiled outside this AVX2 region.)
struct DisplacementRange4 {
    v4d lo_x, lo_y, lo_z, hi_x, hi_y, hi_z;
    v4m bad;
    AMEOTO_INLINE void clear() {
        lo_x = lo_y = lo_z = hi_x = hi_y = hi_z = v4d{0.0, 0.0, 0.0, 0.0};
        bad = v4m{0, 0, 0, 0};
    }
    // dx, dy, dz: displacements since listing (lanes past an array's tail: 0, a displacement of 0).
    // Without NaN: the caller knows otherwise whether one was NaN (update(): see there).
    template <bool NoteNaN = true>
    AMEOTO_INLINE void take(const v4d& dx, const v4d& dy, const v4d& dz) {
        if constexpr (NoteNaN) bad |= (dx != dx) | (dy != dy) | (dz != dz);
        lo_x = _mm256_min_pd(lo_x, dx);
        lo_y = _mm256_min_pd(lo_y, dy);
        lo_z = _mm256_min_pd(lo_z, dz);
        hi_x = _mm256_max_pd(hi_x, dx);
        hi_y = _mm256_max_pd(hi_y, dy);
        hi_z = _mm256_max_pd(hi_z, dz);
    }
    AMEOTO_INLINE double bound2() const {
        if (lane_bits(bad) != 0) return std::numeric_limits<double>::quiet_NaN();
        const v4d rx = hi_x - lo_x, ry = hi_y - lo_y, rz = hi_z - lo_z;
        double range_x = 0.0, range_y = 0.0, range_z = 0.0;
        for (int k = 0; k < 4; ++k) {
            range_x = std::max(range_x, rx[k]);
            range_y = std::max(range_y, ry[k]);
            range_z = std::max(range_z, rz[k]);
        }
        return range_x * range_x + range_y * range_y + range_z * range_z;
    }
};

}  // namespace ameoto::body3d_avx2

#pragma GCC pop_options
