#pragma once
// Drops arriving on an area as real rain delivers them: Poisson arrivals at the impact flux of the
// rain rate, diameters drawn from the flux-weighted size distribution, speeds from Gunn-Kinzer.
//
// Interface:
//   RainSpawner rain(RainSpawner::Config{.area_m2 = 0.707});   // tabulates the flux (allocates once)
//   rain.set_rate(mm_per_h);          // target rate; the current rate ramps there linearly in ramp_s
//   rain.set_rate_now(mm_per_h);      // jump there (a scene's initial state)
//   int n = rain.advance(dt, rng);    // drops arriving during this sample (usually 0 or 1)
//   double d = rain.sample_diameter_m(rng);   // one arriving drop's diameter
//   rain.flux_per_m2_s(mm_per_h)      // impacts m^-2 s^-1 (tabulated, D in [d_min, d_max])
//
// Why the flux weighting: N(D) counts drops in a volume of air; the drops that reach a surface in a
// second are N(D) v(D) dD per m^2, so larger, faster drops are over-represented among impacts.
// Sampling: the truncated exponential N(D) by its inverse CDF, accepted with probability
// v(D) / v(d_max) (rejection), which yields exactly N(D) v(D). Arrivals: a non-homogeneous Poisson
// process by time rescaling (integrated hazard against an Exp(1) threshold), exact while the rate ramps.
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
        MarshallPalmer dsd{};
    };

    explicit RainSpawner(const Config& config);

    void set_rate(double mm_per_h);
    void set_rate_now(double mm_per_h);   // no ramp: for a scene's initial state
    double rate() const { return current_rate_; }
    double target_rate() const { return target_rate_; }

    int advance(double dt, Random& rng);
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
    double v_max_ = 1.0;
    double target_rate_ = 0.0, current_rate_ = 0.0, ramp_step_ = 0.0;
    double arrivals_per_s_ = 0.0;
    double hazard_ = 0.0, threshold_ = 1.0;
    bool threshold_drawn_ = false;
};

}  // namespace ameoto
