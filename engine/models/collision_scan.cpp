// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/collision_scan.hpp"

#include <cstdint>
#include <immintrin.h>

#include "engine/core/cpu_features.hpp"

namespace ameoto {
namespace {

bool portable = false;
const bool has_avx2 = cpu_has_avx2();   // at start-up: no first-call guard on the audio thread

// The reference: collide()'s own tests, mass by mass.
int scan_scalar(const double* x, const double* y, const double* z, int n, const CollisionScanBounds& b, int* out,
                int& near) {
    int count = 0;
    for (int m = 0; m < n; ++m) {
        const double r2 = x[m] * x[m] + y[m] * y[m];
        if (r2 > b.r2_max) continue;
        if (z[m] <= b.band_top && z[m] >= b.band_below) ++near;
        if (z[m] > b.high || z[m] > b.limit || z[m] > b.limit_u) continue;
        out[count++] = m;
    }
    return count;
}

#pragma GCC push_options
#pragma GCC target("avx2")

using v4d = double __attribute__((vector_size(32)));
using v4m = std::int64_t __attribute__((vector_size(32)));

inline __attribute__((always_inline)) v4d load4(const double* p) {
    v4d v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
inline __attribute__((always_inline)) int bits(const v4m& m) {
    return _mm256_movemask_pd(reinterpret_cast<__m256d>(m));
}

// Four masses per vector, the same comparisons as scan_scalar() (ordered: false for NaN, so the negated
// ones pass a NaN as the scalar code does); the tail by scan_scalar().
int scan_avx2(const double* x, const double* y, const double* z, int n, const CollisionScanBounds& b, int* out,
              int& near) {
    const v4d r2_max = {b.r2_max, b.r2_max, b.r2_max, b.r2_max};
    const v4d band_top = {b.band_top, b.band_top, b.band_top, b.band_top};
    const v4d band_below = {b.band_below, b.band_below, b.band_below, b.band_below};
    const v4d high = {b.high, b.high, b.high, b.high};
    const v4d limit = {b.limit, b.limit, b.limit, b.limit};
    const v4d limit_u = {b.limit_u, b.limit_u, b.limit_u, b.limit_u};
    int count = 0, in_band = 0;
    int m = 0;
    for (; m + 4 <= n; m += 4) {
        const v4d px = load4(x + m), py = load4(y + m), pz = load4(z + m);
        const v4d r2 = px * px + py * py;
        const int outside = bits(r2 > r2_max);
        const int band = bits((pz <= band_top) & (pz >= band_below)) & ~outside;
        in_band += __builtin_popcount(static_cast<unsigned>(band));
        int listed = ~bits((pz > high) | (pz > limit) | (pz > limit_u)) & ~outside & 15;
        while (listed) {
            const int k = __builtin_ctz(static_cast<unsigned>(listed));
            out[count++] = m + k;
            listed &= listed - 1;
        }
    }
    near += in_band;
    const int rest = scan_scalar(x + m, y + m, z + m, n - m, b, out + count, near);
    for (int k = 0; k < rest; ++k) out[count + k] += m;
    return count + rest;
}

#pragma GCC pop_options

}  // namespace

int scan_for_collisions(const double* x, const double* y, const double* z, int n, const CollisionScanBounds& bounds,
                        int* out, int& near) {
    if (has_avx2 && !portable) return scan_avx2(x, y, z, n, bounds, out, near);
    return scan_scalar(x, y, z, n, bounds, out, near);
}

void set_portable_collision_scan(bool on) { portable = on; }

}  // namespace ameoto
