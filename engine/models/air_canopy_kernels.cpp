// SPDX-License-Identifier: GPL-3.0-or-later
// The in-air canopy's per-sample loops, baseline and AVX2 (air_canopy_kernels.hpp).
#include "engine/models/air_canopy_kernels.hpp"

#include <cstring>

#include "engine/core/cpu_features.hpp"
#include "engine/core/lane_sums.hpp"

namespace ameoto {

namespace {

// Kick q' += T p, then the exact transition; a = (q'[n+1] - q'[n]) / T. Restrict: the loop vectorises
// (element by element: the same bits at any width). Inlined into each kernel below, so that each is
// compiled for its own target (an inline function is not compiled on its own inside the AVX2 region).
[[gnu::always_inline]] inline void advance_loop(std::size_t modes, double* __restrict q, double* __restrict qd, double* __restrict p,
                                                double* __restrict a, const double* __restrict a11, const double* __restrict a12,
                                                const double* __restrict a21, const double* __restrict a22, double t, double inverse_t) {
    for (std::size_t k = 0; k < modes; ++k) {
        const double kicked = qd[k] + t * p[k];
        const double q_next = a11[k] * q[k] + a12[k] * kicked;
        const double qd_next = a21[k] * q[k] + a22[k] * kicked;
        a[k] = (qd_next - qd[k]) * inverse_t;
        q[k] = q_next;
        qd[k] = qd_next;
        p[k] = 0.0;
    }
}

void advance_baseline(std::size_t modes, double* q, double* qd, double* p, double* a, const double* a11, const double* a12,
                      const double* a21, const double* a22, double t, double inverse_t) {
    advance_loop(modes, q, qd, p, a, a11, a12, a21, a22, t, inverse_t);
}

double taps_baseline(const double* a, const double* x, const double* b, const double* y, std::size_t n) {
    return lane_sums::dot2(a, x, b, y, n);
}

}  // namespace

// (clang, the fuzz build's compiler, ignores the pragma: there the "AVX2" pair is baseline code too, which
// is slower, not wrong.)
#pragma GCC push_options
#pragma GCC target("avx2")

namespace {

// The same loop as advance_baseline, compiled for AVX2.
void advance_avx2(std::size_t modes, double* q, double* qd, double* p, double* a, const double* a11, const double* a12,
                  const double* a21, const double* a22, double t, double inverse_t) {
    advance_loop(modes, q, qd, p, a, a11, a12, a21, a22, t, inverse_t);
}

// lane_sums::dot2 written again here (its inline body compiled in this region would be another
// definition of one inline function: the linker could hand the AVX2 one to baseline callers).
using v4d = double __attribute__((vector_size(32)));

double taps_avx2(const double* a, const double* x, const double* b, const double* y, std::size_t n) {
    v4d lo{}, hi{};
    std::size_t k = 0;
    for (; k + 8 <= n; k += 8) {
        v4d a0, a1, x0, x1, b0, b1, y0, y1;
        std::memcpy(&a0, a + k, sizeof a0);
        std::memcpy(&a1, a + k + 4, sizeof a1);
        std::memcpy(&x0, x + k, sizeof x0);
        std::memcpy(&x1, x + k + 4, sizeof x1);
        std::memcpy(&b0, b + k, sizeof b0);
        std::memcpy(&b1, b + k + 4, sizeof b1);
        std::memcpy(&y0, y + k, sizeof y0);
        std::memcpy(&y1, y + k + 4, sizeof y1);
        lo += a0 * x0 + b0 * y0;
        hi += a1 * x1 + b1 * y1;
    }
    const v4d s4 = lo + hi;
    double s = (s4[0] + s4[2]) + (s4[1] + s4[3]);
    for (; k < n; ++k) s += a[k] * x[k] + b[k] * y[k];
    return s;
}

}  // namespace

#pragma GCC pop_options

const AirKernels& air_kernels_baseline() {
    static const AirKernels k{advance_baseline, taps_baseline, false};
    return k;
}

const AirKernels& air_kernels() {
    static const AirKernels k = cpu_has_avx2() ? AirKernels{advance_avx2, taps_avx2, true} : air_kernels_baseline();
    return k;
}

}  // namespace ameoto
