// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Checks whose bound is the normal build's speed or memory, not the program's correctness: the audio's
// real time (no xrun, no late bundle, a drop sounding at its timetag's sample) and a process's RSS.
// Under AddressSanitizer + UndefinedBehaviorSanitizer (scripts/build-sanitized --all) they cannot hold:
// the audio thread runs several times slower than real time, and ASan keeps freed blocks in its
// quarantine (up to 256 MB) instead of reusing them. There such a check is printed, not asserted; the
// test still runs everything before it, so the sanitizers still watch the code it drives. The normal
// build asserts every one, unchanged (timing_scale.hpp's switch: the compiler's own __SANITIZE_ADDRESS__).
//
// Interface:
//   AMEOTO_CHECK_UNLESS_SANITIZED(expr);               // CHECK(expr), or under the sanitizers a MESSAGE
//                                                      // naming expr and why it is not asserted
//   if (ameoto::test::stop_here_if_sanitized("why")) return;
//                                                      // the rest of a test case is a real-time bound:
//                                                      // under the sanitizers print why and stop there
// docs/reliability.md ("Sanitizers") lists every use.

#include <doctest/doctest.h>

#include <string>

#include "tests/support/timing_scale.hpp"

namespace ameoto::test {

inline bool stop_here_if_sanitized(const char* why) {
    if (!sanitized_build()) return false;
    const std::string text = std::string("the rest is not asserted under the sanitizers (tests/support/sanitizer_bounds.hpp): ") + why;
    MESSAGE(text);
    return true;
}

}  // namespace ameoto::test

#define AMEOTO_CHECK_UNLESS_SANITIZED(expr)                                                                           \
    do {                                                                                                          \
        if (::ameoto::test::sanitized_build())                                                                    \
            MESSAGE((std::string("not asserted under the sanitizers (tests/support/sanitizer_bounds.hpp): " #expr " is ") + \
                     ((expr) ? "true" : "false")));                                                               \
        else                                                                                                      \
            CHECK(expr);                                                                                          \
    } while (false)
