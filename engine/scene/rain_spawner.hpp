// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Drops arriving on an area as real rain delivers them: Poisson arrivals at the impact flux of the
// rain rate, diameters drawn from the flux-weighted size distribution, speeds from Gunn-Kinzer.
//
// Interface:
//   RainSpawner rain(RainSpawner::Config{.area_m2 = 0.707});   // tabulates the flux (allocates nothing;
//                                     // throws std::invalid_argument on a bad area, size range or DSD)
//   RainSpawner::Config{.dsd = DropSizeDistribution::joss_drizzle()}   // any DSD (drop_size_distribution.hpp)
//   rain.set_rate(mm_per_h);          // target rate; the current rate ramps there linearly in ramp_s
//   rain.set_rate_now(mm_per_h);      // jump there (a scene's initial state)
//   int n = rain.advance(dt, rng);    // drops arriving during this sample (usually 0 or 1)
//   int n = rain.advance(dt, rng, s); // the same with the flux scaled by s >= 0 over this step (wind on a
//                                     // tilted surface: engine/scene/wind.hpp); s = 1 is advance(dt, rng)
//   double d = rain.sample_diameter_m(rng);   // one arriving drop's diameter
//   rain.flux_per_m2_s(mm_per_h)      // impacts m^-2 s^-1 (tabulated per DSD, D in [d_min, d_max])
//
// Why the flux weighting: N(D) counts drops in a volume of air; the drops that reach a surface in a
// second are N(D) v(D) dD per m^2, so larger, faster drops are over-represented among impacts.
// Sampling, exponential DSDs (mu = 0): the truncated exponential N(D) by its inverse CDF, accepted with
// probability v(D) / v(d_max) (rejection), which yields exactly N(D) v(D). At most 64 tries: acceptance
// is 25-57 % for the three exponential presets over 0.01..500 mm/h, so running out (the last proposal is
// kept) has a chance below 1e-8 per drop (1e-11 at 1 mm/h). Gamma DSDs (mu != 0): proposals from a
// truncated exponential of rate Lambda / (1 + mu) (mu > 0: the classical exponential envelope of a gamma,
// whose bound sits at the gamma's mean) or Lambda (mu < 0), accepted with probability
// g(D) / max g * v(D) / v(d_max), g = D^mu exp(-(Lambda - rate) D): exact N(D) v(D) again. At most 1000
// tries; acceptance is 15-42 % for mu from -0.9 to 16 (computed by quadrature), so the cap is never met. The flux table is built from the configured DSD, so
// counts follow it (and its N0 mode: drop_size_distribution.hpp says whether the water equals R).
// Arrivals: a non-homogeneous Poisson process by time rescaling (integrated hazard against an Exp(1)
// threshold), exact while the rate ramps or the flux scale changes.
// No allocation after construction; safe on the audio thread.

#include <array>

#include "engine/core/random.hpp"
#include "engine/scene/drop_size_distribution.hpp"

namespace ameoto {

class RainSpawner {
public:
    struct Config {
        double area_m2 = 1.0;
        double d_min_mm = 0.5;   // smaller drops carry too little momentum to hear on a canopy
        double d_max_mm = 6.0;   // larger drops break up in air (Gunn-Kinzer's table ends at 5.8)
        double ramp_s = 1.0;     // a rate change takes this long
        DropSizeDistribution dsd{};   // Marshall-Palmer by default
    };

    explicit RainSpawner(const Config& config);

    void set_rate(double mm_per_h);
    void set_rate_now(double mm_per_h);   // no ramp: for a scene's initial state
    double rate() const { return current_rate_; }
    double target_rate() const { return target_rate_; }

    int advance(double dt, Random& rng) { return advance(dt, rng, 1.0); }
    int advance(double dt, Random& rng, double flux_scale);
    double sample_diameter_m(Random& rng) const;
    double flux_per_m2_s(double mm_per_h) const;
    const Config& config() const { return config_; }

    static constexpr double max_rate_mm_per_h = 500.0;

private:
    static constexpr int table_size = 128;
    static constexpr double table_min_rate = 0.01;   // mm/h; below, flux falls linearly to 0 at 0

    Config config_;
    std::array<double, table_size> log_flux_{};
    double log_rate_min_ = 0.0, log_rate_step_ = 0.0;
    void update_shape();   // Lambda and mu at the current rate (a few pow calls; only when it changes)

    double v_max_ = 1.0;
    double lambda_ = 1.0, mu_ = 0.0;   // the DSD's shape at current_rate_
    double target_rate_ = 0.0, current_rate_ = 0.0, ramp_step_ = 0.0;
    double arrivals_per_s_ = 0.0;
    double hazard_ = 0.0, threshold_ = 1.0;
    bool threshold_drawn_ = false;
};

}  // namespace ameoto
