// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The "drop tiers" rows of `ameoto bench accuracy`: the scene's levels of detail (full: a lattice drop;
// template: its recorded contact force replayed; texture: a noise grain of its template's energy and
// colour; docs/rain.md "Levels of detail") on the umbrella scene, each drop forced into one tier.
//
// Interface:
//   TierRender r = render_tier(LodTier::texture, rate_mm_per_h, seconds, seed);   // the scene's output
//                                                   (warm_s: rendered first, untimed, not kept)
//   BandSpectrum s = long_term_spectrum(r, 48000);     // Welch PSD summed into third-octave bands
//   double d = band_distance_db(s, reference);         // log-spectral distance of two long-term spectra
//   double l = level_difference_db(s, reference);      // broadband level, dB
//   std::vector<TierRow> rows = measure_tiers(options);   // cost and error of each tier
//
// Error, against the full tier (the reference: its own error is 0 by definition): the same rain (same
// seed, so the same drops: sizes, arrival samples, points; the grains draw their noise from a generator
// of their own, renderer.hpp) rendered with every drop forced full, then template, then texture, at
// `error_rate_mm_per_h` (light enough that the lattice pool, 64 drops of up to 0.5 s, never fills: a
// drop it could not take would play as a template; counted and reported). Both stereo channels' Welch
// PSDs (Hann, half overlap) are added and summed into third-octave bands 25 Hz..20 kHz;
// D = sqrt(mean over bands of (10 log10 P / P_full)^2), bands more than 60 dB under the reference's
// loudest left out (a tier's band floored there: a lost band scores large but finite). Welch, 16384 points
// (2.9 Hz bins, so the lowest band holds two). For the template this is the long-term form of impact_templates_test's drop-by-drop
// comparison. For the texture it is the only meaningful one: a grain is noise with its template's
// energy and spectral centroid, not its waveform, so only the statistics of many drops (the long-term
// spectral envelope and level) can match; what the texture promises is its templates' energy per drop
// (texture_grains.hpp, docs/rain.md), so the broadband level difference is reported beside D.
// Cost: CPU per drop, as `ameoto bench scene` measures it (bench_scene.hpp): the umbrella scene with
// every rain drop forced into the tier against the same scene dry, thread CPU time, median of `runs`
// pairs; full at the error run's rate (bench scene's 0.3 mm/h fills the lattice pool when every
// drop is forced full, and the drops it cannot take play as templates), template and texture at 200 mm/h (enough drops to
// rise above the machine's noise). A cost under the noise is reported as measured (<= 0) and drawn at
// the chart's floor.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/render/lod_governor.hpp"

namespace ameoto::client {

struct TierRender {
    std::vector<float> left, right;
    double cpu_s = 0.0;
    std::uint64_t drops = 0, full = 0, template_ = 0, texture = 0;   // rain drops given each tier
};

constexpr int third_octave_bands = 30;   // base-2 third octaves, centres 1 kHz * 2^(k/3), k = -16..13: 24.8 Hz..20.2 kHz

struct BandSpectrum {
    std::array<double, third_octave_bands> centre_hz{}, power{};
};

struct TierRow {
    std::string name;          // full, template, texture
    double rate_mm_per_h = 0;  // the cost run's
    double ns_per_drop = 0;    // CPU per drop over its life (<= 0: under the noise)
    double lsd_db = 0;         // long-term spectrum against the full tier's
    double level_db = 0;       // broadband level against the full tier's
    std::uint64_t drops = 0;   // in the error run
    std::uint64_t fallbacks = 0;   // drops the error run could not give this tier (full: the pool was full)
    std::uint64_t cost_fallbacks = 0;   // the same, over the cost runs
};

struct TierOptions {
    double error_rate_mm_per_h = 0.1;   // about 80 drops per second on the umbrella: the pool never fills
    double error_seconds = 4.0;
    double cost_seconds = 2.0;     // audio seconds per timed run
    int runs = 3;
    std::uint64_t seed = 3;
};

TierRender render_tier(LodTier tier, double rate_mm_per_h, double seconds, std::uint64_t seed, double warm_s = 0.0);
BandSpectrum long_term_spectrum(const TierRender& render, double sample_rate);
double band_distance_db(const BandSpectrum& x, const BandSpectrum& reference);
double level_difference_db(const BandSpectrum& x, const BandSpectrum& reference);
double spectral_centroid_hz(const BandSpectrum& s);   // power-weighted mean of the band centres
const char* tier_name(LodTier tier);
std::vector<TierRow> measure_tiers(const TierOptions& options);

}  // namespace ameoto::client
