// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 19, part 2, over its whole range: the server's canopy in air (its air-loaded modes heard as
// dipoles, each force's instantaneous push below a crossover and its compressible push above) against the reference's band levels at dx 5 mm, the
// finest run, cached here because it takes 23 minutes. air_canopy_test.cpp runs the reference itself on
// its cheap grid (80-630 Hz), which ties this cache to the reference as it is. Each band is read as a
// brick wall between its edges and through IEC 61260-1 class-1 band filters (screen_far_field.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "engine/models/air_canopy.hpp"
#include "engine/models/canopy.hpp"
#include "engine/reference/canopy_bands.hpp"
#include "engine/reference/screen_far_field.hpp"
#include "tests/engine/models/air_canopy_bands_reference.hpp"
#include "tests/support/timing_scale.hpp"

using namespace ameoto;

namespace {

// A pair the server's model misses by more than 3 dB against the 5 mm reference (docs/canopy-air.md,
// "Band levels with the push"), held where it is so that it cannot drift further unseen.
struct KnownMiss {
    int strike, listener;
    double hz, measured_db;
};
// Node 12 at 3 m at 198 Hz (+3.3 dB as a brick wall, +2.4 through the band filters, where the modes'
// resonances near the band's edge count half in each band): the skirt of the second in-phase mode
// (168.7 Hz; 163.1 Hz in compressible air). The reference there: -81.9, -84.3, -83.3, -83.9 dB at 10,
// 7.5, 5 and 3.75 mm (docs/canopy-air.md).
constexpr KnownMiss known_misses[] = {
    {1, 2, 198.425, +3.3},
};

// Read through IEC 61260-1 class-1 band filters (screen_far_field.hpp), where a resonance on a band's edge
// counts half in each band: node 43 at 3 m at 99 Hz (+3.007 dB), the skirt of the lowest mode (84.6 Hz;
// 80.9 Hz in compressible air, docs/canopy-air.md), 2.8-3.0 dB high at all six under-shaft and 3 m pairs
// (3.2-3.5 dB against the 3.75 mm run, whose level there, -82.1 dB, is the 10 mm run's: the 5 mm run's
// -81.6 is the grids' scatter).
constexpr KnownMiss known_filtered_misses[] = {
    {2, 2, 99.2126, +3.0},
};

template <std::size_t N>
const KnownMiss* known_in(const KnownMiss (&list)[N], int strike, int listener, double hz) {
    for (const KnownMiss& m : list)
        if (m.strike == strike && m.listener == listener && std::abs(m.hz / hz - 1.0) < 1e-3) return &m;
    return nullptr;
}

}  // namespace

TEST_CASE("air canopy: band levels 63 Hz-4 kHz against the 5 mm reference, three strikes, three listeners") {
    // The strikes and listeners of `ameoto reference canopy-bands` (its --json reference_db is the cache).
    const Canopy shape(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / 48000.0);
    const Point2 c = shape.panel_centroid(0);
    const Point2 points[3] = {c, {c.x * 1.35, c.y + 0.03}, {c.x * 0.55, c.y - 0.02}};
    const int expected_nodes[3] = {24, 12, 43};   // the centroid, towards the hem, towards the shaft
    int misses = 0, modes_alone_misses = 0, pairs = 0, filtered_misses = 0;
    double worst = 0.0, filtered_worst = 0.0;
    // Under the sanitizers the centroid only: the other two strikes run the same code for another node.
    const int strikes = test::sanitized_build() ? 1 : 3;
    reference::CanopyBandsSetup s;
    s.reference.duration_s = 0.2;
    s.low_hz = 63.0;
    s.high_hz = 4000.0;
    // Every pair past 3 dB is one of the known ones, on the same side and no further off than measured.
    auto held = [](const KnownMiss* m, double d) {
        REQUIRE(m != nullptr);
        CHECK(d * m->measured_db > 0.0);
        CHECK(std::abs(d) < std::abs(m->measured_db) + 0.3);
    };
    Canopy in_air(shape);   // the air's modes built once for the three strikes
    in_air.set_air(build_air_canopy_modes(in_air, 1.0 / s.fast_rate_hz));
    for (int k = 0; k < strikes; ++k) {
        const int node = shape.locate(points[k].x, points[k].y).node;
        REQUIRE(node == expected_nodes[k]);   // the cache's strikes
        const reference::FastCanopyBands f = reference::fast_canopy_bands(s, in_air, node);
        REQUIRE(f.fast_push.size() == 3);
        for (int l = 0; l < 3; ++l) {
            const auto& heard = f.fast_push[static_cast<std::size_t>(l)];
            const auto& alone = f.fast[static_cast<std::size_t>(l)];
            REQUIRE(heard.size() == test::canopy_bands_5mm_bands);
            std::string row;
            for (std::size_t b = 0; b < heard.size(); ++b) {
                REQUIRE(heard[b].centre_hz == doctest::Approx(test::canopy_bands_5mm_hz[b]).epsilon(1e-4));
                const double d = heard[b].level_db - test::canopy_bands_5mm_db[k][l][b];
                const double d_alone = alone[b].level_db - test::canopy_bands_5mm_db[k][l][b];
                char text[32];
                std::snprintf(text, sizeof text, " %.0f %+.1f", heard[b].centre_hz, d);
                row += text;
                ++pairs;
                worst = std::max(worst, std::abs(d));
                modes_alone_misses += std::abs(d_alone) > 3.0 ? 1 : 0;
                if (std::abs(d) <= 3.0) continue;
                ++misses;
                INFO("node " << node << ", listener " << l << ", " << heard[b].centre_hz << " Hz: " << d << " dB");
                held(known_in(known_misses, k, l, heard[b].centre_hz), d);
            }
            MESSAGE("node " << node << " listener " << l << ":" << row);
            // The same record read through the band filters, against the reference's read the same way.
            const std::vector<reference::BandLevel> filtered = reference::third_octave_levels(
                f.fast_push_pressure[static_cast<std::size_t>(l)], 1.0 / s.fast_rate_hz, s.low_hz, s.high_hz, reference::BandFilter::iec61260);
            REQUIRE(filtered.size() == test::canopy_bands_5mm_bands);
            std::string filtered_row;
            for (std::size_t b = 0; b < filtered.size(); ++b) {
                const double d = filtered[b].level_db - test::canopy_bands_5mm_filtered_db[k][l][b];
                char text[32];
                std::snprintf(text, sizeof text, " %.0f %+.1f", filtered[b].centre_hz, d);
                filtered_row += text;
                filtered_worst = std::max(filtered_worst, std::abs(d));
                if (std::abs(d) <= 3.0) continue;
                ++filtered_misses;
                INFO("through the band filters: node " << node << ", listener " << l << ", " << filtered[b].centre_hz << " Hz: " << d << " dB");
                held(known_in(known_filtered_misses, k, l, filtered[b].centre_hz), d);
            }
            MESSAGE("node " << node << " listener " << l << " through the band filters:" << filtered_row);
        }
    }
    MESSAGE(filtered_misses << " pairs past 3 dB through the band filters (worst " << filtered_worst << " dB)");
    MESSAGE(misses << " of " << pairs << " band-listener pairs past 3 dB with the push (worst " << worst << " dB), " << modes_alone_misses
                   << " with the modes' taps alone");
    CHECK(pairs == strikes * 3 * 19);
    if (strikes < 3) return;
    CHECK(misses <= 1);
    CHECK(filtered_misses <= 1);
    // The push is what brings the bands above the modes in, and the instantaneous push those below them:
    // the modes' two taps alone miss 17 pairs.
    CHECK(modes_alone_misses >= 15);
}
