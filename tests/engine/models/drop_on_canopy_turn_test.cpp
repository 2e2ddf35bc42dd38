// SPDX-License-Identifier: GPL-3.0-or-later
// DropOnCanopy::turn_head in air (drop_on_canopy_turn.cpp, dipole_radiation.hpp): the dipole model's
// taps re-mixed from each panel's own when the head turns, and its own taps again at rest. (In vacuum:
// renderer_listener_test.cpp, on the renderer's output.)

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "engine/models/ambisonics.hpp"
#include "engine/models/drop_on_canopy.hpp"

TEST_CASE("umbrella in air, stereo: a head turned round swaps the panels' taps between the speakers; turned back, its own") {
    ameoto::DropOnCanopyConfig config;
    config.capacity = 1;
    config.max_diameter = 4e-3 * (1.0 + 1e-9);
    config.air = true;
    config.channels = 2;
    config.listener = ameoto::ListenerStyle::panned;
    ameoto::DropOnCanopy umbrella(config);   // one air-loaded canopy: building its modes is the cost here
    const ameoto::DipoleRadiation& dipole = umbrella.dipole();
    REQUIRE(dipole.modes() > 0);
    std::vector<std::pair<double, double>> rest;
    double largest = 0.0;
    for (int ch = 0; ch < 2; ++ch)
        for (int q = 0; q < dipole.modes(); ++q) {
            rest.push_back(dipole.coefficients(ch, q));
            largest = std::max({largest, std::abs(rest.back().first), std::abs(rest.back().second)});
        }
    const auto at = [&](int ch, int q) { return rest[static_cast<std::size_t>(ch * dipole.modes() + q)]; };
    // Yaw 180: a panel at azimuth a is heard at a + 180, and on a pair at +-90 degrees pan_gains swaps
    // its two gains; the taps are linear in them (dipole_radiation.hpp), so each speaker's re-mixed taps
    // are the other's own, to rounding (1e-9 of the largest tap: sums of a few hundred terms).
    REQUIRE(umbrella.turn_head(ameoto::head_rotation(M_PI, 0.0, 0.0), 0));   // at once
    double worst = 0.0;
    for (int ch = 0; ch < 2; ++ch)
        for (int q = 0; q < dipole.modes(); ++q) {
            const auto now = dipole.coefficients(ch, q), other = at(1 - ch, q);
            worst = std::max({worst, std::abs(now.first - other.first), std::abs(now.second - other.second)});
        }
    MESSAGE("taps after yaw 180 against the other speaker's: worst " << worst / largest << " of the largest");
    CHECK(worst <= 1e-9 * largest);
    // The audio stays finite through a drop on the turned canopy.
    REQUIRE(umbrella.drop(4e-3, 0.0, 0.05, 0.2));
    float f[2];
    bool finite = true, sound = false;
    for (int n = 0; n < 1200; ++n) {
        umbrella.process_frame(f);
        finite = finite && std::isfinite(f[0]) && std::isfinite(f[1]);
        sound = sound || f[0] != 0.0f;
    }
    CHECK(finite);
    CHECK(sound);
    // Back at rest: the layout's own taps, bit for bit.
    REQUIRE(umbrella.turn_head(ameoto::head_rotation(0.0, 0.0, 0.0), 0));
    bool same = true;
    for (int ch = 0; ch < 2; ++ch)
        for (int q = 0; q < dipole.modes(); ++q) same = same && dipole.coefficients(ch, q) == at(ch, q);
    CHECK(same);
}
