// SPDX-License-Identifier: GPL-3.0-or-later
// The texture level of detail (engine/models/texture_grains.hpp): grains carry their template's energy.
#include "engine/models/texture_grains.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "engine/core/fft.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/core/random.hpp"
#include "engine/models/drop.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto;

namespace {

DropOnCanopyConfig scene_config() {
    DropOnCanopyConfig c;
    c.max_diameter = 6.1e-3;
    return c;
}

const ImpactTemplateTable& templates() {
    static const ImpactTemplateTable t = record_impact_templates(scene_config());
    return t;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

const TextureCalibration& calibration() {
    static const TextureCalibration c = calibrate_texture(scene_config(), templates());
    return c;
}

}  // namespace

TEST_CASE("texture: the calibration grows with the drop and stays in the audible band") {
    const TextureCalibration& c = calibration();
    REQUIRE(c.diameters_m.size() == 11u);   // every fifth of the 51 template sizes
    for (std::size_t k = 0; k < c.diameters_m.size(); ++k) {
        CAPTURE(c.diameters_m[k]);
        CHECK(c.energy_fs2[k] > 0.0);
        CHECK(c.centre_hz[k] > 50.0);
        CHECK(c.centre_hz[k] < 24000.0);
        CHECK(c.decay_s[k] > 1e-4);
        CHECK(c.decay_s[k] < 0.5);
    }
    // A 5 mm drop carries far more energy than a 1 mm one (its momentum is 40 times larger).
    CHECK(c.energy(5e-3) > 100.0 * c.energy(1e-3));
    // Interpolation reproduces the grid and stays between neighbours.
    CHECK(c.energy(c.diameters_m[3]) == ameoto::test::relative(c.energy_fs2[3]));
    const double mid = std::sqrt(c.diameters_m[3] * c.diameters_m[4]);
    CHECK(c.energy(mid) >= std::min(c.energy_fs2[3], c.energy_fs2[4]));
    CHECK(c.energy(mid) <= std::max(c.energy_fs2[3], c.energy_fs2[4]));
}

TEST_CASE("texture: a grain's energy is its calibrated size's, on average (within 10 %)") {
    // The bed adds E (1 - d^2) to a band's power for energy E; the noise is normalised by the band-pass's
    // exact noise gain. This measures the energy that comes out. 400 grains per size, mono, each rendered
    // alone until it has died away (0.3 s: over 30 decay times).
    const TextureCalibration& c = calibration();
    for (double d : {0.6e-3, 1.5e-3, 3e-3, 5e-3}) {
        CAPTURE(d);
        TextureGrains grains(c, 48000.0);
        Random rng(7);
        double energy = 0.0;
        const int count = 400;
        for (int g = 0; g < count; ++g) {
            REQUIRE(grains.add(d, 0.0, 998.0, 0.0, 1, rng));
            for (int i = 0; i < 14400; ++i) {
                float frame[1] = {0.0f};
                grains.render(frame, 1, rng);
                energy += static_cast<double>(frame[0]) * frame[0];
            }
        }
        CHECK(energy / count == ameoto::test::relative(c.energy(d)).epsilon(0.10));
    }
}

TEST_CASE("texture: the bed pans, costs the same for any number of grains, and never allocates") {
    TextureGrains grains(calibration(), 48000.0);
    Random rng(1);
    ameoto::test::RtAudit audit;
    double left = 0.0, right = 0.0;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int i = 0; i < 10000; ++i) CHECK(grains.add(2e-3, 0.0, 998.0, 1.5707963, 2, rng));   // hard left
        CHECK(grains.active() == 10000);
        for (int i = 0; i < 480; ++i) {
            float frame[2] = {0.0f, 0.0f};
            grains.render(frame, 2, rng);
            left += frame[0] * frame[0];
            right += frame[1] * frame[1];
        }
    }
    CHECK(audit.violations() == 0);
    CHECK(left > 0.0);
    CHECK(right < 1e-6 * left);
    // active(): the grains added within the last 5 decay times; after a second of silence, none.
    for (int i = 0; i < 48000; ++i) {
        float frame[2] = {0.0f, 0.0f};
        grains.render(frame, 2, rng);
    }
    CHECK(grains.active() == 0);
    // Twelve bands from 150 Hz, log-spaced, to 16 kHz at 48 kHz.
    CHECK(grains.band_centre_hz(0) == doctest::Approx(150.0));
    CHECK(grains.band_centre_hz(TextureGrains::bands - 1) == doctest::Approx(16000.0));
}

TEST_CASE("texture: the calibration from one canopy (its own or the caller's) copied per size is the one from a canopy built per size, bit for bit") {
    // calibrate_texture builds the canopy once (CanopyBuild::shared); per_size builds it for every
    // calibrated size. A short template grid (11 sizes: 3 calibrated) keeps this quick.
    TemplateGrid grid;
    grid.min_diameter_m = 2e-3;
    grid.step_ratio = 1.1;
    grid.max_diameter_m = 2e-3 * std::pow(1.1, 10.5);
    grid.seconds = 0.005;
    const ImpactTemplateTable t = record_impact_templates(scene_config(), grid);
    REQUIRE(t.diameters_m.size() == 11u);
    const TextureCalibration shared = calibrate_texture(scene_config(), t, CanopyBuild::shared);
    const TextureCalibration fresh = calibrate_texture(scene_config(), t, CanopyBuild::per_size);
    REQUIRE(fresh.diameters_m.size() == 3u);
    CHECK(same_bits(shared.diameters_m, fresh.diameters_m));
    CHECK(same_bits(shared.speeds_m_per_s, fresh.speeds_m_per_s));
    CHECK(same_bits(shared.energy_fs2, fresh.energy_fs2));
    CHECK(same_bits(shared.log_energy, fresh.log_energy));
    CHECK(same_bits(shared.centre_hz, fresh.centre_hz));
    CHECK(same_bits(shared.decay_s, fresh.decay_s));
    CHECK(std::memcmp(&shared.density, &fresh.density, sizeof(double)) == 0);
    for (double e : fresh.energy_fs2) CHECK(e > 0.0);   // each size was heard
    // The caller's canopy (UmbrellaScene's), likewise.
    const TextureCalibration given = calibrate_texture(scene_config(), t, DropOnCanopy::fresh_canopy(scene_config()));
    CHECK(same_bits(given.energy_fs2, fresh.energy_fs2));
    CHECK(same_bits(given.centre_hz, fresh.centre_hz));
    CHECK(same_bits(given.decay_s, fresh.decay_s));
}

TEST_CASE("texture: in air the sizes' scenes share one design of the push filters, and the calibration is a per-size build's bit for bit") {
    // The umbrella's canopy in air with the push (the built-in scenes'): with one canopy for all sizes
    // each size's scene takes the first's push filters (DipoleRadiation's sibling); per_size builds
    // everything again for every size.
    DropOnCanopyConfig air = scene_config();
    air.air = true;
    air.air_push = true;
    TemplateGrid grid;
    grid.min_diameter_m = 2e-3;
    grid.step_ratio = 1.1;
    grid.max_diameter_m = 2e-3 * std::pow(1.1, 5.5);   // 6 sizes: 2 calibrated
    grid.seconds = 0.005;
    const ImpactTemplateTable t = record_impact_templates(air, grid);
    REQUIRE(t.diameters_m.size() == 6u);
    const TextureCalibration shared = calibrate_texture(air, t, DropOnCanopy::fresh_canopy(air));
    const TextureCalibration fresh = calibrate_texture(air, t, CanopyBuild::per_size);
    REQUIRE(fresh.diameters_m.size() == 2u);
    CHECK(same_bits(shared.energy_fs2, fresh.energy_fs2));
    CHECK(same_bits(shared.centre_hz, fresh.centre_hz));
    CHECK(same_bits(shared.decay_s, fresh.decay_s));
    for (double e : fresh.energy_fs2) CHECK(e > 0.0);
}

// The bed puts a grain where its calibrated centroid is (texture_grains.hpp): split between the two bands
// whose outputs' power centroids lie around it, linearly in f, so that the bed's long-term power centroid
// (what bench accuracy compares with the full tier's) is the grains' f_c. Measured on 4 s of grains at
// one f_c each, 20 a second: the centroid of the output's power spectrum within 10 % of f_c. Measured:
// +8.5 % at 600 Hz, +4.3 % at 1 kHz, +1.1 % at 2.5 kHz, +0.2 % at 6 kHz; what remains at the low end is
// not explained yet (the bands' unit normalisation is the suspect). The old split, by nominal centres,
// put a grain 1.6-1.9 times too high there (band_power_centroid_hz over band_centre_hz).
TEST_CASE("texture: the bed's power centroid is the grains' calibrated centroid") {
    for (const double fc : {600.0, 1000.0, 2500.0, 6000.0}) {
        CAPTURE(fc);
        TextureCalibration cal;
        cal.diameters_m = {1e-3, 5e-3};
        cal.speeds_m_per_s = {arrival_speed(1e-3, 998.0), arrival_speed(5e-3, 998.0)};
        cal.energy_fs2 = {1e-4, 1e-4};
        cal.log_energy = {std::log(1e-4), std::log(1e-4)};
        cal.centre_hz = {fc, fc};
        cal.decay_s = {0.01, 0.01};
        TextureGrains grains(cal, 48000.0);
        CHECK(grains.band_power_centroid_hz(0) > grains.band_centre_hz(0));   // the skirts
        Random rng(7);
        const int n = 4 * 48000;
        std::vector<double> out(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
            if (i % 2400 == 0) REQUIRE(grains.add(2e-3, 0.0, 998.0, 0.0, 1, rng));
            float frame[1] = {0.0f};
            grains.render(frame, 1, rng);
            out[static_cast<std::size_t>(i)] = frame[0];
        }
        // Welch: 16 384-point segments, half overlap, Hann.
        const std::size_t m = 16384;
        std::vector<double> power(m / 2, 0.0);
        for (std::size_t start = 0; start + m <= out.size(); start += m / 2) {
            std::vector<std::complex<double>> a(m);
            for (std::size_t j = 0; j < m; ++j)
                a[j] = out[start + j] * (0.5 - 0.5 * std::cos(2.0 * constants::pi * static_cast<double>(j) / m));
            fft_in_place(a);
            for (std::size_t k = 1; k < m / 2; ++k) power[k] += std::norm(a[k]);
        }
        double weighted = 0.0, total = 0.0;
        for (std::size_t k = 1; k < m / 2; ++k) {
            weighted += power[k] * 48000.0 * static_cast<double>(k) / m;
            total += power[k];
        }
        MESSAGE("grains at ", fc, " Hz: bed's power centroid ", weighted / total, " Hz");
        CHECK(weighted / total == doctest::Approx(fc).epsilon(0.10));
    }
}
