// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/phase_sincos.hpp: against std::sin and std::cos over its whole range, exact
// where they are, odd and even bit for bit, and across the quadrants' edges.
#include "engine/core/phase_sincos.hpp"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "engine/core/physical_constants.hpp"
#include "engine/core/random.hpp"

using ameoto::phase_sincos;
using ameoto::phase_sincos_limit;

namespace {

// Two units in the last place of 1: what Cephes' polynomials and the three-part reduction promise
// against a correctly rounded result (glibc's sin and cos are within an ulp of it).
constexpr double tolerance = 4.5e-16;

struct Worst {
    double sine = 0.0, cosine = 0.0;
    void take(double x) {
        double s = 0.0, c = 0.0;
        phase_sincos(x, s, c);
        sine = std::max(sine, std::abs(s - std::sin(x)));
        cosine = std::max(cosine, std::abs(c - std::cos(x)));
    }
};

}  // namespace

TEST_CASE("phase sincos: within two ulp of libm's sine and cosine from 1e-9 rad to its limit") {
    ameoto::Random rng(7);
    for (const double scale : {1e-9, 1e-3, 1.0, 10.0, 100.0, 1e4, phase_sincos_limit}) {
        Worst w;
        for (int i = 0; i < 200000; ++i) w.take(scale * (2.0 * rng.uniform() - 1.0));
        INFO("|x| up to " << scale << ": worst sine " << w.sine << ", cosine " << w.cosine);
        CHECK(w.sine <= tolerance);
        CHECK(w.cosine <= tolerance);
    }
}

TEST_CASE("phase sincos: exact at 0, odd and even bit for bit, and right on either side of each quadrant's edge") {
    double s = 1.0, c = 0.0;
    phase_sincos(0.0, s, c);
    CHECK(s == 0.0);
    CHECK(c == 1.0);
    ameoto::Random rng(11);
    for (int i = 0; i < 10000; ++i) {
        const double x = 50.0 * rng.uniform();
        double sp = 0.0, cp = 0.0, sn = 0.0, cn = 0.0;
        phase_sincos(x, sp, cp);
        phase_sincos(-x, sn, cn);
        CHECK(std::bit_cast<std::uint64_t>(sn) == std::bit_cast<std::uint64_t>(-sp));
        CHECK(std::bit_cast<std::uint64_t>(cn) == std::bit_cast<std::uint64_t>(cp));
    }
    // Each multiple of pi / 4 (the reduction's rounding changes quadrant at the odd ones), a hair either side.
    Worst w;
    for (int q = -40; q <= 40; ++q) {
        const double edge = q * ameoto::constants::pi / 4.0;
        for (const double d : {-1e-12, -1e-15, 0.0, 1e-15, 1e-12}) w.take(edge + d);
    }
    INFO("worst sine " << w.sine << ", cosine " << w.cosine);
    CHECK(w.sine <= tolerance);
    CHECK(w.cosine <= tolerance);
}
