// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The in-air canopy's two per-sample loops over its modes, each in a baseline and an AVX2 version that
// give the same bits: the modes' step (air_canopy.cpp) and each channel's dipole taps
// (dipole_radiation.cpp). Between them they are most of a scene's work in air.
//
// Interface (audio thread; no allocation):
//   const AirKernels& k = air_kernels();         // AVX2 where the CPU has it (cpu_features.hpp), else baseline
//   k.advance(modes, q, qd, p, a, t11, t12, t21, t22, T, 1 / T);   // one step of every mode (below)
//   k.taps(a, x, b, y, n)                        // sum a[k] x[k] + b[k] y[k] (lane_sums.hpp's order)
//   air_kernels_baseline()                       // the baseline pair (the tests compare the two)
//
// Bit identity: the same IEEE operations in the same order in both (the step is element by element; the
// taps keep lane_sums.hpp's eight running sums), no fused multiply-add (this file's sources are compiled
// with -ffp-contract=off, engine/CMakeLists.txt), so a render's bits do not depend on the CPU.

#include <cstddef>

namespace ameoto {

struct AirKernels {
    // Kick q' += T p, then the exact transition [q, q'] <- [t11 t12; t21 t22] [q, q' + T p] (the modal
    // integrator's, core/integrators/modal.hpp); a = (q'[n+1] - q'[n]) / T, the step's mean acceleration
    // (what the radiation reads, dipole_radiation.hpp); p is cleared for the next step.
    void (*advance)(std::size_t modes, double* q, double* qd, double* p, double* a, const double* t11, const double* t12,
                    const double* t21, const double* t22, double t, double inverse_t);
    double (*taps)(const double* a, const double* x, const double* b, const double* y, std::size_t n);
    bool avx2 = false;
};

const AirKernels& air_kernels();
const AirKernels& air_kernels_baseline();

}  // namespace ameoto
