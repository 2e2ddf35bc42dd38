// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// relative(x): doctest::Approx(x) whose epsilon is relative to |x| at any size. Plain Approx has scale 1,
// which makes its epsilon absolute below 1 (epsilon 0.01 accepts 0.0013 +/- 0.01).
//
// With scale 0 an expected 0 demands exact equality; a check against 0 writes its absolute bound out
// (CHECK(std::abs(a) < tol)) instead.

#include <doctest/doctest.h>

namespace ameoto::test {

inline doctest::Approx relative(double expected) { return doctest::Approx(expected).scale(0.0); }

}  // namespace ameoto::test
