// SPDX-License-Identifier: GPL-3.0-or-later
// The fast air-loaded canopy (engine/models/air_loading.hpp) against the FDTD reference
// (engine/reference/canopy_in_air.hpp): issue 19's first 10 panel modes in air within 3 % of its finest run.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/canopy.hpp"
#include "engine/reference/canopy_in_air.hpp"
#include "tests/support/sanitizer_bounds.hpp"

namespace {

// The finest reference run, `ameoto reference canopy --dx 0.005` (2026-12-07, 510 s of reference; 0.4 s
// recorded, each peak read in its first 0.1 s): the struck panel's modes 1-10 in air, Hz. Converging:
// from 10 mm (122.8, 224.4, 226.4, 315.0, ...) through 7.5 mm (121.1, 220.2, 223.6, 311.8, ...), mode 4
// came down from 4.1 % over the fast model to 2.3 % (docs/air-reference.md, "The canopy's copies").
constexpr double kCanopyReference5mm[10] = {122.2, 222.2, 225.3, 309.5, 330.9, 331.4, 388.4, 461.7, 465.9, 503.8};
// The reference at 25 mm (this test's own live run, 2026-12-07, a few seconds), which ties the cache to
// the reference as it is: its three lowest modes.
constexpr double kCanopyReference25mm[3] = {125.746, 234.781, 233.736};

}  // namespace

TEST_CASE("canopy in air: the fast model's first 10 panel modes against the reference") {
    using ameoto::reference::CanopyInAirSetup;
    CanopyInAirSetup s;   // the setup of `ameoto reference canopy`
    s.margin_m = 0.15;
    s.duration_s = 0.1;
    const ameoto::Canopy canopy(s.geometry, s.material, 1.0 / 48000.0);
    const ameoto::AirLoadedModes air =
        ameoto::air_loaded_modes(canopy, ameoto::canopy_added_mass(canopy, ameoto::constants::air_density));
    const std::vector<double> fast = ameoto::reference::modal_panel_modes(s, canopy, air, 10);
    REQUIRE(fast.size() == 10);
    for (int q = 0; q < 10; ++q) {
        const double e = fast[static_cast<std::size_t>(q)] / kCanopyReference5mm[q] - 1.0;
        std::printf("panel mode %d: reference (5 mm) %.1f Hz, fast %.1f Hz, %+.1f %%\n", q + 1, kCanopyReference5mm[q],
                    fast[static_cast<std::size_t>(q)], 100.0 * e);
        // Issue 19: within 3 % (measured: mode 4 -2.2 %, the rest within 1.6 %).
        CHECK(std::abs(e) < 0.03);
    }
    // Live: the reference itself at 25 mm (a few seconds), so that the cache is this reference's: it
    // gives the cached 25 mm figures (to 0.02 Hz: the same arithmetic, whatever the compiler's rounding),
    // which lie above the 5 mm ones (a coarse
    // grid puts the lowest modes 3-6 % high, never low: docs/air-reference.md). Under the sanitizers
    // panel_modes_in_air runs in air_reference_test.cpp ("the canopy in air, struck"); this 25 mm run is
    // left to Release (15 s there).
    if (ameoto::test::stop_here_if_sanitized("the reference's panel modes run under them in air_reference_test.cpp")) return;
    s.dx = 0.025;
    const std::vector<ameoto::reference::PanelMode> coarse = ameoto::reference::panel_modes_in_air(s, 3);
    for (int q = 0; q < 3; ++q) {
        const double hz = coarse[static_cast<std::size_t>(q)].air_hz;
        std::printf("panel mode %d: reference at 25 mm %.3f Hz (cached %.3f), %+.1f %% of the 5 mm figure\n", q + 1, hz,
                    kCanopyReference25mm[q], 100.0 * (hz / kCanopyReference5mm[q] - 1.0));
        CHECK(std::abs(hz - kCanopyReference25mm[q]) <= 0.02);
        CHECK(hz > kCanopyReference5mm[q]);
    }
}

TEST_CASE("canopy in air: the pencil finds the fast model's own canopy modes in a panel mode's projection") {
    // The fast model is modal, so the canopy modes in its projections are known exactly (air.omega): the
    // estimator of `ameoto reference canopy` (panel_mode_components, 0.4 s) must find them. Panel mode 4:
    // in 0.1 s its copies at 288, 307 and 322 Hz blend into one Hann peak (302.6 Hz); the pencil must
    // place each within 0.05 Hz of the exact mode (measured: under 0.01 Hz) and carry at least 10 % of
    // the record's energy.
    using ameoto::reference::CanopyInAirSetup;
    CanopyInAirSetup s;
    s.duration_s = 0.4;
    const ameoto::Canopy canopy(s.geometry, s.material, 1.0 / 48000.0);
    const ameoto::AirLoadedModes air =
        ameoto::air_loaded_modes(canopy, ameoto::canopy_added_mass(canopy, ameoto::constants::air_density));
    const ameoto::reference::PanelProjections p = ameoto::reference::modal_panel_projections(s, canopy, air, 4);
    const std::vector<ameoto::reference::DampedSinusoid> c =
        ameoto::reference::panel_mode_components(p.velocity[3], p.sample_interval_s, p.vacuum_hz[3], s.pulse_s);
    double total = 0.0;
    for (const auto& x : c) total += ameoto::reference::record_energy(x, s.duration_s);
    int found = 0;
    for (const auto& x : c) {
        if (ameoto::reference::record_energy(x, s.duration_s) < 0.1 * total) continue;
        double nearest = 1e9;
        for (Eigen::Index m = 0; m < air.omega.size(); ++m)
            nearest = std::min(nearest, std::abs(air.omega[m] / (2.0 * ameoto::constants::pi) - x.frequency_hz));
        std::printf("panel mode 4 (fast, pencil): %.2f Hz, %.2f /s, %.0f %% of the energy, %.3f Hz from a canopy mode\n",
                    x.frequency_hz, x.damping_per_s, 100.0 * ameoto::reference::record_energy(x, s.duration_s) / total, nearest);
        CHECK(nearest < 0.05);
        ++found;
    }
    CHECK(found >= 3);
}
