// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench levels`: every built-in scene's level at its listener against rain rate. Each scene is
// rendered offline with the renderer ameotod runs (engine/render/renderer.hpp, configured as
// `ameoto render scene` does: same seed, adaptive LOD off, so the figures are reproducible) at its
// default rain, 25, 50 and 100 mm/h, and measured at the listener: LAeq (A-weighted, IEC 61672-1,
// a_weighting.hpp) and the unweighted Leq, dB re 20 uPa, with the slope in dB per decade of rain rate
// fitted by least squares over those rates. docs/levels.md holds the table and compares it with the
// measured rain-noise levels (shared/reference/acoustics.md, section 4).
//
// Interface (control thread; measure_* run their renders on worker threads of their own):
//   int status = run_levels_bench(words, io);                // words: everything after "ameoto bench"
//   LevelReading r = measure_level(scene, 25.0, 4.0, 1);     // one render: the levels at the listener
//   SceneLevels s = measure_scene_levels(scene, rates, 4.0, 1, 2);   // a scene at several rates, 2 threads
//   double k = slope_db_per_decade(s.levels, true);          // LAeq's least-squares slope
//   std::vector<double> rates = level_rates(20.0);           // 20, 25, 50, 100 (sorted, no repeats)
//
// What is measured: the pressure at the listening point, a mono render (ListenerStyle::panned with one
// channel: every source summed at the listener; a stereo render's two channels sum in power to it, as
// the panning law is constant power). The first settle_seconds are rendered and not counted: plates
// and the canopy start at rest, and their modes need a few decay times to reach the rain's steady
// power (tin's lowest modes ring for about 2 s at eta 0.01; what they hold is a small part of the
// A-weighted sum). Then `seconds` of audio at 48 kHz: Leq = 10 log10(mean(p^2) / (20 uPa)^2), with
// p = sample x RendererConfig::full_scale_pa.

#include <cstdint>
#include <string>
#include <vector>

#include "clients/ameoto/command_io.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto::client {

inline constexpr double levels_settle_seconds = 1.0;
inline constexpr double levels_sample_rate = 48000.0;

struct LevelReading {
    double rain_mm_per_h = 0.0;
    double laeq_db = 0.0;        // A-weighted Leq, dB re 20 uPa
    double leq_db = 0.0;         // unweighted (Z) Leq, dB re 20 uPa
    double render_seconds = 0.0; // wall time of this render
    bool finite = true;          // every sample finite
};

struct SceneLevels {
    SceneDescription scene;
    std::vector<LevelReading> levels;   // by rate, ascending
    double slope_a_db_per_decade = 0.0;
    double slope_z_db_per_decade = 0.0;
};

std::vector<double> level_rates(double default_rain_mm_per_h);
LevelReading measure_level(const SceneDescription& scene, double rain_mm_per_h, double seconds, std::uint64_t seed);
SceneLevels measure_scene_levels(const SceneDescription& scene, const std::vector<double>& rates, double seconds,
                                 std::uint64_t seed, int threads);
double slope_db_per_decade(const std::vector<LevelReading>& levels, bool a_weighted);
// The levels of a signal (pascals), skipping nothing: the meter under measure_level, for tests.
LevelReading levels_of(const std::vector<double>& pressure_pa, double sample_rate);

std::string levels_bench_usage();
int run_levels_bench(const CommandWords& words, const CommandIo& io);

}  // namespace ameoto::client
