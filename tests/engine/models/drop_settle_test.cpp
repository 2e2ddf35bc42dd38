// SPDX-License-Identifier: GPL-3.0-or-later
// DropOnCanopy's settling (drop_on_canopy.hpp, "Settling"): pieces of liquid that are done are parked,
// and what that changes in the sound is bounded.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "engine/core/fft.hpp"
#include "engine/models/drop_on_canopy.hpp"

namespace {

using ameoto::DropOnCanopy;
using ameoto::DropOnCanopyConfig;

struct SettleRun {
    std::vector<float> sound;
    ameoto::DropOnCanopyStats stats;
    ameoto::DropPoolStats pool;
};

// One 5 mm water drop at terminal speed on the default nylon canopy, half way out on panel 0, mono far
// field: the scene of ameoto bench drop.
SettleRun run(bool settle, double seconds) {
    DropOnCanopyConfig c;
    c.max_diameter = 5.2e-3;
    c.settle = settle;
    DropOnCanopy scene(c);
    REQUIRE(scene.drop(5e-3, 0.0, 0.25, 0.0));
    SettleRun r;
    r.sound.assign(static_cast<std::size_t>(seconds * c.sample_rate), 0.0f);
    float* out[1] = {r.sound.data()};
    scene.process(static_cast<int>(r.sound.size()), out);
    r.stats = scene.stats();
    r.pool = scene.pool().stats();
    return r;
}

// Octave band energies (band b: 62.5 * 2^b Hz centre, edges at centre / sqrt 2 and centre sqrt 2), from
// the whole signal's spectrum (zero-padded to a power of two).
std::vector<double> octave_energies(const std::vector<float>& x, double rate) {
    std::size_t n = 1;
    while (n < x.size()) n *= 2;
    std::vector<std::complex<double>> a(n);
    for (std::size_t i = 0; i < x.size(); ++i) a[i] = x[i];
    ameoto::fft_in_place(a);
    std::vector<double> bands(9, 0.0);
    for (std::size_t k = 1; k < n / 2; ++k) {
        const double f = k * rate / static_cast<double>(n);
        const int b = static_cast<int>(std::floor(std::log2(f / 62.5) + 0.5));
        if (b >= 0 && b < 9) bands[static_cast<std::size_t>(b)] += std::norm(a[k]);
    }
    return bands;
}

}  // namespace

TEST_CASE("drop_settle: parking done liquid keeps a 5 mm drop's sound within 0.5 dB in every octave, 63 Hz to 16 kHz") {
    // The tolerance is this change's own (issue 19, part 5): what is parked is liquid that has left the
    // canopy or lies on it slower than 5 cm/s along the normal; it loads the membrane only with its
    // weight and mass (a 5 mm drop's 65 mg on a 5.3 g panel), so the sound may move by a fraction of a
    // dB where the parked parcels lay, and not at all before the first parking.
    const double seconds = 0.5;
    const SettleRun before = run(false, seconds), after = run(true, seconds);
    MESSAGE(after.pool.parked << " masses parked; " << after.pool.coarse_steps << " coarse steps (before: "
                              << before.pool.coarse_steps << ")");
    CHECK(after.pool.parked > 50);   // most of the splash leaves the canopy or comes to rest within 0.5 s
    CHECK(before.pool.parked == 0);
    CHECK(after.pool.coarse_steps > before.pool.coarse_steps);   // what it buys: the rest flies coarsely
    CHECK(after.pool.coarse_interrupted == 0);   // the lower coarse floor: no piece touched during one
    // Conservation: parked masses keep their mass.
    CHECK(after.stats.masses == after.stats.masses_at_spawn);
    CHECK(after.stats.mass_kg == after.stats.mass_at_spawn_kg);
    // The impact itself (the first 5 ms: the drop is whole or just shattering, nothing is done yet) is
    // the same to the bit.
    const std::size_t impact = static_cast<std::size_t>(0.005 * 48000);
    bool same = true;
    for (std::size_t i = 0; i < impact; ++i) same = same && before.sound[i] == after.sound[i];
    CHECK(same);
    const std::vector<double> a = octave_energies(before.sound, 48000.0), b = octave_energies(after.sound, 48000.0);
    for (std::size_t band = 0; band < a.size(); ++band) {
        const double db = 10.0 * std::log10(b[band] / a[band]);
        char text[80];
        std::snprintf(text, sizeof text, "octave %.0f Hz: %+.3f dB", 62.5 * std::pow(2.0, band), db);
        MESSAGE(text);
        CHECK(std::fabs(db) < 0.5);
    }
}

TEST_CASE("drop_settle: a drop whose liquid is all done retires; bad rest speeds are refused") {
    const SettleRun after = run(true, 1.5);
    MESSAGE(after.pool.retired << " retired, " << after.pool.parked << " parked");
    CHECK(after.pool.retired == 1);   // settled and gone well before its 30 s lifetime
    CHECK(after.stats.active_drops == 0);
    DropOnCanopyConfig c;
    c.max_diameter = 5.2e-3;
    c.rest_speed_m_per_s = -1.0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c.rest_speed_m_per_s = NAN;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
}
