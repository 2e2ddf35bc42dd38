// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/panning: constant-power panning over stereo and rings of speakers.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/models/panning.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

TEST_CASE("pan_gains keep constant power") {
    for (int channels : {1, 2, 3, 4, 6, 8, 16}) {
        CAPTURE(channels);
        double worst = 0.0;
        int unused_nonzero = 0, negative = 0;
        for (int i = 0; i <= 2000; ++i) {
            const double az = -2.0 * kPi + 6.0 * kPi * i / 2000.0;
            const auto g = ameoto::pan_gains(az, channels);
            double power = 0.0;
            for (int c = 0; c < ameoto::max_pan_channels; ++c) {
                const double gc = g[static_cast<std::size_t>(c)];
                unused_nonzero += c >= channels && gc != 0.0;   // outputs beyond `channels` stay silent
                negative += gc < 0.0;
                power += gc * gc;
            }
            worst = std::max(worst, std::abs(power - 1.0));
        }
        // panning.hpp: constant power, sum of squares 1 (rounding only).
        CHECK(worst < 1e-12);
        CHECK(unused_nonzero == 0);
        CHECK(negative == 0);
    }
    // Stereo: +90 deg (left) is hard left, -90 deg hard right, front is centred.
    auto g = ameoto::pan_gains(kPi / 2, 2);
    CHECK(g[0] == doctest::Approx(1.0));
    CHECK(g[1] == doctest::Approx(0.0).epsilon(1e-12).scale(1.0));
    g = ameoto::pan_gains(-kPi / 2, 2);
    CHECK(g[0] == doctest::Approx(0.0).epsilon(1e-12).scale(1.0));
    CHECK(g[1] == doctest::Approx(1.0));
    g = ameoto::pan_gains(0.0, 2);
    CHECK(g[0] == ameoto::test::relative(std::sqrt(0.5)).epsilon(1e-12));
    CHECK(g[1] == ameoto::test::relative(std::sqrt(0.5)).epsilon(1e-12));
    // Ring of 4 from front-left, clockwise: speakers at 45, -45, -135, 135 deg.
    const double speaker[4] = {kPi / 4, -kPi / 4, -3 * kPi / 4, 3 * kPi / 4};
    for (int s = 0; s < 4; ++s) {
        CAPTURE(s);
        g = ameoto::pan_gains(speaker[s], 4);
        CHECK(g[static_cast<std::size_t>(s)] == doctest::Approx(1.0).epsilon(1e-9));
    }
    // Straight ahead is half way between front-left and front-right.
    g = ameoto::pan_gains(0.0, 4);
    CHECK(g[0] == ameoto::test::relative(std::sqrt(0.5)).epsilon(1e-12));
    CHECK(g[1] == ameoto::test::relative(std::sqrt(0.5)).epsilon(1e-12));
    CHECK(ameoto::pan_gains(1.234, 1)[0] == 1.0);
}
