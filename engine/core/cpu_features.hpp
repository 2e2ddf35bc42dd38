// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the CPU the engine runs on can do, for the kernels that pick their code at run time (the build
// itself stays baseline x86-64, so one binary runs everywhere).
//
// Interface:
//   if (cpu_has_avx2()) ...   // the AVX2 kernels may run (Body3D's step, the laned canopy)
//   if (cpu_has_avx512f()) ... // the AVX-512 kernels may run (the laned canopy of 8 or 16 panels)

namespace ameoto {

inline bool cpu_has_avx2() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2");
}

inline bool cpu_has_avx512f() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f");
}

}  // namespace ameoto
