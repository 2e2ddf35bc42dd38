// SPDX-License-Identifier: GPL-3.0-or-later
// Third-octave band levels read as a brick wall and through class-1 band filters (screen_far_field.hpp).
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "engine/core/physical_constants.hpp"
#include "engine/reference/screen_far_field.hpp"

using namespace ameoto;
using namespace ameoto::reference;

namespace {

constexpr double band_rate = 48000.0;
const double band_width = std::pow(2.0, 1.0 / 6.0) - std::pow(2.0, -1.0 / 6.0);   // of the centre frequency

// A unit impulse, |X(f)| = 1 at every frequency, over `seconds`.
std::vector<double> unit_impulse(double seconds) {
    std::vector<double> x(static_cast<std::size_t>(seconds * band_rate), 0.0);
    x[0] = band_rate;
    return x;
}

// A decaying tone at `hz`, 1/s decay `rate`, over `seconds`.
std::vector<double> ringing(double hz, double rate, double seconds) {
    std::vector<double> x(static_cast<std::size_t>(seconds * band_rate));
    for (std::size_t n = 0; n < x.size(); ++n) {
        const double t = static_cast<double>(n) / band_rate;
        x[n] = std::exp(-rate * t) * std::sin(2.0 * constants::pi * hz * t);
    }
    return x;
}

double level_at(const std::vector<BandLevel>& bands, double centre_hz) {
    for (const BandLevel& b : bands)
        if (std::abs(b.centre_hz / centre_hz - 1.0) < 0.01) return b.level_db;
    FAIL("no band at " << centre_hz << " Hz");
    return 0.0;
}

}  // namespace

TEST_CASE("band filters: a 3rd-order Butterworth band-pass, -3 dB on the band's edges") {
    const double centre = 1000.0;
    CHECK(third_octave_filter_power(centre, centre) == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(third_octave_filter_power(centre, centre * std::pow(2.0, 1.0 / 6.0)) == doctest::Approx(0.5).epsilon(1e-12));
    CHECK(third_octave_filter_power(centre, centre * std::pow(2.0, -1.0 / 6.0)) == doctest::Approx(0.5).epsilon(1e-12));
    // One octave off the centre: IEC 61260-1 class 1 asks at least 40-odd dB for a third octave.
    CHECK(10.0 * std::log10(third_octave_filter_power(centre, 2.0 * centre)) < -45.0);
    CHECK(10.0 * std::log10(third_octave_filter_power(centre, 0.5 * centre)) < -45.0);
    CHECK(third_octave_filter_power(centre, 0.0) == 0.0);
}

TEST_CASE("band filters: a flat spectrum's band energy is the band's width, times pi / 3 through the filter") {
    // Glasser's master theorem: integral of g(Q (W - 1/W)) dW over W > 0 is (1 / Q) integral of g, so a
    // band-pass of low-pass prototype 1 / (1 + x^6) passes (pi / 3) (W2 - W1) of a flat spectrum (+0.20 dB
    // over the brick wall), whatever the band's relative width. Independent of the code's quadrature.
    const std::vector<double> x = unit_impulse(0.2);
    const std::vector<BandLevel> ideal = third_octave_levels(x, 1.0 / band_rate, 63.0, 4000.0);
    const std::vector<BandLevel> filtered = third_octave_levels(x, 1.0 / band_rate, 63.0, 4000.0, BandFilter::iec61260);
    REQUIRE(ideal.size() == 19);
    REQUIRE(filtered.size() == ideal.size());
    for (std::size_t k = 0; k < ideal.size(); ++k) {
        CAPTURE(ideal[k].centre_hz);
        const double width_db = 10.0 * std::log10(2.0 * ideal[k].centre_hz * band_width);
        // The brick wall's sum is within one frequency step (1 / (4 x 0.2 s)) of the band's width.
        CHECK(std::abs(ideal[k].level_db - width_db) < 10.0 * std::log10(1.0 + 1.25 / (ideal[k].centre_hz * band_width)));
        CHECK(std::abs(filtered[k].level_db - (width_db + 10.0 * std::log10(constants::pi / 3.0))) < 0.01);
    }
}

TEST_CASE("band filters: a resonance inside a band is its energy; on an edge, half in each band") {
    // A tone ringing down at 5 /s over 0.4 s: energy integral of x^2, about (1 - e^(-2 a T)) / (4 a).
    const double rate = 5.0, seconds = 0.4;
    const double energy_db = 10.0 * std::log10((1.0 - std::exp(-2.0 * rate * seconds)) / (4.0 * rate));
    const std::vector<double> inside = ringing(1000.0, rate, seconds);
    CHECK(std::abs(level_at(third_octave_levels(inside, 1.0 / band_rate, 800.0, 1250.0, BandFilter::iec61260), 1000.0) - energy_db) < 0.1);
    CHECK(std::abs(level_at(third_octave_levels(inside, 1.0 / band_rate, 800.0, 1250.0), 1000.0) - energy_db) < 0.1);
    // On the edge between the 1000 and 1260 Hz bands: the brick wall puts it all on one side, the band
    // filters half (-3 dB) in each, as an analyser reads it.
    const double edge = 1000.0 * std::pow(2.0, 1.0 / 6.0);
    const std::vector<double> on_edge = ringing(edge, rate, seconds);
    const std::vector<BandLevel> f = third_octave_levels(on_edge, 1.0 / band_rate, 800.0, 1600.0, BandFilter::iec61260);
    CHECK(std::abs(level_at(f, 1000.0) - (energy_db - 3.01)) < 0.3);
    CHECK(std::abs(level_at(f, 1000.0 * std::pow(2.0, 1.0 / 3.0)) - (energy_db - 3.01)) < 0.3);
    const std::vector<BandLevel> w = third_octave_levels(on_edge, 1.0 / band_rate, 800.0, 1600.0);
    CHECK(std::abs(level_at(w, 1000.0) - level_at(w, 1000.0 * std::pow(2.0, 1.0 / 3.0))) < 1.0);   // the edge splits the peak's bins
    // 1 % either side of the edge, the brick wall jumps; the filters' skirt moves about 1 dB a percent.
    const std::vector<BandLevel> below = third_octave_levels(ringing(edge * 0.99, rate, seconds), 1.0 / band_rate, 800.0, 1600.0);
    const std::vector<BandLevel> above = third_octave_levels(ringing(edge * 1.01, rate, seconds), 1.0 / band_rate, 800.0, 1600.0);
    CHECK(level_at(below, 1000.0) - level_at(above, 1000.0) > 6.0);
    const std::vector<BandLevel> below_f =
        third_octave_levels(ringing(edge * 0.99, rate, seconds), 1.0 / band_rate, 800.0, 1600.0, BandFilter::iec61260);
    const std::vector<BandLevel> above_f =
        third_octave_levels(ringing(edge * 1.01, rate, seconds), 1.0 / band_rate, 800.0, 1600.0, BandFilter::iec61260);
    CHECK(level_at(below_f, 1000.0) - level_at(above_f, 1000.0) < 2.5);
}
