// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// How much longer a test waits for the programs under test when they are built with AddressSanitizer
// (scripts/build-sanitized): one switch for every bound that depends on the machine's speed (start-up,
// a program's run to its end), never a weaker bound in the normal build.
//
// Interface:
//   test::sanitized_build()                 // true in the ASan + UBSan build (build-asan/)
//   test::timing_scale()                    // 1 normally; 4 under the sanitizers
//   auto t = test::scaled(10s);             // 10 s normally, 40 s under the sanitizers
//
// Why 4: ameotod's start-up (the scene build: drop lattices, impact templates, texture calibration)
// measured 2.3 s of CPU in the Release build and 15.5 s under ASan + UBSan at -O2 (about 6 times)
// (docs/reliability.md, "Sanitizers", gives the command); 4 on a 30 s start-up bound gives 120 s:
// room for that and for a CPU shared with another test. A test
// whose bound is the audio's real time (not a wait for a program) is not scaled: it is skipped under
// the sanitizers with a printed reason (sanitizer_bounds.hpp), and listed in docs/reliability.md.
// The switch is the compiler's own: gcc and clang define __SANITIZE_ADDRESS__ with -fsanitize=address,
// so a sanitized test binary cannot forget to set it and a normal one cannot set it by mistake.

#include <chrono>

namespace ameoto::test {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool sanitized_build() { return true; }
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool sanitized_build() { return true; }
#else
constexpr bool sanitized_build() { return false; }
#endif
#else
constexpr bool sanitized_build() { return false; }
#endif

constexpr int timing_scale() { return sanitized_build() ? 4 : 1; }

template <typename Rep, typename Period>
constexpr std::chrono::duration<Rep, Period> scaled(std::chrono::duration<Rep, Period> bound) {
    return bound * timing_scale();
}

}  // namespace ameoto::test
