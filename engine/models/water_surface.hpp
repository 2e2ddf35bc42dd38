// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A water surface (pond, puddle) struck by rain: the faint impact of each drop and the bubbles some drops
// trap, summed into the pressure heard in the air 1 m from the impacts.
//
// Interface:
//   WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = 96000});   // allocates its pools; throws
//                                                                       // std::invalid_argument on a bad config
//   ---- audio thread: no allocation, no locks, no logging ----
//   Entrainment e = water.strike(diameter_m, speed_m_per_s, rng);       // a drop lands (now)
//   double p = water.sample();                       // next sample: Pa at 1 m
//   water.process(out, frames);                      // the next `frames` samples (double or float), overwritten
//   water.stats(); water.active_bubbles(); water.reset();
//
//   Entrainment e = draw_entrainment(diameter_m, rng);   // the size law alone (what strike() uses)
//   entrainment_probability(diameter_m); splash_class(diameter_m);
//
// Output: pressure (Pa) at bubble::reference_distance_m = 1 m from the impact point, in the air, as if
// every drop struck the same point: one WaterSurface is one patch heard from one direction. A scene
// applies distance (1/r), delay and panning per patch, and uses several patches to spread the rain.
// The same seed and the same strikes give the same samples at any block size (the bubbles are summed in
// the order they started, sample(), process(1) and process(256) alike).
//
// A strike starts two sounds:
//
// 1. The impact (for every drop with speed > 0). The drop's force on the surface is the pulse of
//    engine/models/impact_force.hpp (Soto 2014 / Gordillo 2018: impulse m V over tau = D / V, sqrt rise),
//    reused here; on a deep pool its shape differs from the rigid-wall law it was fitted to, its impulse
//    and time scale do not. A force F on a free water surface is almost silent in the air: the
//    (incompressible) water yields under it, and the surface moves down under the drop and up around it
//    with no net volume. Linear potential flow below the surface gives a surface acceleration of
//    wavenumber k equal to -|k| p_s(k) / rho_w, and the Rayleigh integral over that surface, at angle
//    theta from the vertical, picks k = (w / c) sin(theta):
//      p(r) = (rho_air / rho_w) sin(theta) / (2 pi r c_air) dF/dt       (|w F| spectrum; we keep dF/dt,
//    the causal signal with the same power spectrum as the exact Hilbert-transformed one). That is the
//    rigid-baffle dipole times rho_air / rho_w = 1.2e-3. Peaks at 1 m, terminal speed, sin = 1: 1 mm drop
//    18 dB SPL (at 48 kHz) / 21 dB (96 kHz), 3 mm 47 / 50 dB, 5 mm 57 / 60 dB, against 41 dB for the
//    0.22 mm bubble. (The sqrt rise makes dF/dt's spectrum fall only as f^(-1/2), so the sampled peak
//    grows with the bandwidth; the spectrum below 20 kHz does not depend on the rate.) This matches
//    Phillips et al. (Sci. Rep. 8:9515, 2018): the impact and splash are nearly silent in air; the
//    bubble is the sound. sin(theta) is WaterSurfaceConfig::sin_angle_from_vertical (1: grazing, the
//    loudest; a listener beside a pond hears most drops at 0.7-1). Deep water assumed (depth well above
//    1 / k: a puddle shallower than about 1 cm is quieter at low frequencies by tanh(k h), not modelled).
//
// 2. At most one bubble (bubble.hpp), by the drop's size, at terminal speed (Pumphrey, Crum & Bjorno,
//    JASA 85:1518, 1989; Pumphrey & Elmore, JFM 220:539, 1990; Medwin et al., JASA 92:1613, 1992;
//    physics.md 4). Classes and the laws chosen:
//      tiny   D < 0.8 mm:   no bubble (impact only; they are quiet).
//      small  0.8-1.1 mm:   "regular entrainment": one bubble almost every time, p = 0.95 (Pumphrey et
//             al. found one at every impact in their range; 0.95 allows for the shape oscillations and the
//             band's fuzzy edges in real rain). Radius: the bubble shrinks across the band towards its
//             upper edge, where it vanishes (Oguz & Prosperetti, JFM 219:143, 1990; Pumphrey & Elmore
//             1990), so a falls log-linearly from 0.24 mm at 0.8 mm (13.7 kHz) to 0.14 mm at 1.1 mm
//             (23.5 kHz), times a scatter e^u, u uniform in +-0.05: every pitch in 13.0-24.7 kHz, the
//             13-25 kHz band of light-rain noise. The most frequent (smallest) drops give the largest,
//             loudest bubbles, about 0.22 mm: light rain's spectrum peaks at 15.5 kHz (a = 0.21 mm),
//             as observed (14-16 kHz, Pumphrey et al. 1989).
//      medium 1.1-2.2 mm:   "mostly impact only": p = 0.05 (ASSUMPTION: Medwin et al. saw none; 5 %
//             stands for "mostly").
//      large  D > 2.2 mm:   bubbles trapped irregularly by the splash: p = 0.2 at 2.2 mm rising linearly
//             to 0.5 at 4 mm and above (ASSUMPTION: "irregularly"; larger drops splash more violently).
//      Irregular (medium and large) radius: log-uniform between 0.1 mm and D / 4 (bubble diameter up to
//      half the drop's: 2.2 mm drops reach 0.55 mm, 6.0 kHz; 6 mm drops 1.5 mm, 2.2 kHz), the broad
//      1-35 kHz range of large drops' bubbles (Medwin et al. 1992; Nystuen's drop-size classes, J. Atmos.
//      Oceanic Technol. 18:1640, 2001). Being louder (a^(3/2)) and longer (lower d), the largest of
//      them carry most of their energy: large drops bring the lower pitches.
//    Why the irregular laws matter: a 1.5 mm bubble is 25 dB louder than a 0.22 mm one and rings 13 times
//    longer, so the rare irregular bubbles set the level below 10 kHz. With the laws above, light rain
//    (1-2 mm/h, Marshall-Palmer, 20 s on 1 m^2, 8 seeds) peaks at 15.4-15.6 kHz, 4-10 dB above the
//    strongest 1 kHz band below 10 kHz (physics.md check 10); the low band catches up at 5-10 mm/h, as
//    underwater rain noise does (drizzle's 15 kHz peak, heavy rain's flatter spectrum: Nystuen 2001).
//    A narrow irregular range would not: 0.33-0.55 mm for every medium drop, even at p = 0.02, piles
//    that energy into a 6-7 kHz hump above the 15 kHz peak at 2 mm/h (7 seeds of 8); the breadth of
//    the range matters more than p.
//    The classes are by size alone, for drops at (or near) terminal speed, i.e. rain: slow drips would
//    need the speed-size map of Oguz & Prosperetti; the secondary splashes of large drops (type III
//    bubbles, Nystuen & Medwin 1993), the few-ms delay between impact and pinch-off, and per-bubble scatter
//    of the initial amplitude are left out. Each strike draws exactly two uniforms from rng, whatever it
//    decides, so the stream stays aligned.
//
// Capacity: a full bubble pool drops the new bubble and counts it (stats().bubbles_dropped); a full
// impact pool (2048 pulses) drops the impact and counts it. A bubble whose pitch is above the band limit
// of the sample rate is not played (stats().bubbles_above_band; bubble.hpp).

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/bubble.hpp"

namespace ameoto {

class ImpactPool;

enum class SplashClass { tiny, small, medium, large };

struct Entrainment {
    SplashClass splash = SplashClass::tiny;
    bool bubble = false;       // a bubble is trapped
    double radius_m = 0.0;     // its radius, when bubble
};

namespace entrainment {
inline constexpr double small_min_m = 0.8e-3;    // Pumphrey, Crum & Bjorno 1989; Medwin et al. 1992
inline constexpr double small_max_m = 1.1e-3;
inline constexpr double medium_max_m = 2.2e-3;
inline constexpr double small_probability = 0.95;
inline constexpr double medium_probability = 0.05;
inline constexpr double large_probability_min = 0.2;    // at 2.2 mm
inline constexpr double large_probability_max = 0.5;    // from 4 mm
inline constexpr double large_probability_full_m = 4.0e-3;
inline constexpr double small_radius_at_min_m = 0.24e-3;   // at D = 0.8 mm (13.7 kHz)
inline constexpr double small_radius_at_max_m = 0.14e-3;   // at D = 1.1 mm (23.5 kHz)
inline constexpr double small_scatter = 0.05;              // ln-radius, uniform +-
inline constexpr double irregular_radius_min_m = 0.1e-3;   // 33 kHz
inline constexpr double irregular_radius_per_diameter = 0.25;   // the largest: D / 4
}  // namespace entrainment

SplashClass splash_class(double diameter_m);
double entrainment_probability(double diameter_m);
// Draws exactly two uniforms from rng. A non-finite or non-positive diameter: tiny, no bubble.
Entrainment draw_entrainment(double diameter_m, Random& rng);

struct WaterSurfaceConfig {
    double sample_rate_hz = 48000.0;
    int max_bubbles = 256;                 // ringing at once
    double sin_angle_from_vertical = 1.0;  // impact directivity, [0, 1]
};

struct WaterSurfaceStats {
    std::uint64_t strikes = 0;              // accepted drops
    std::uint64_t rejected = 0;             // strike() refused: non-finite or non-positive diameter or speed
    std::array<std::uint64_t, 4> by_class{};   // strikes per SplashClass
    std::uint64_t bubbles_entrained = 0;    // strikes that trapped a bubble
    std::uint64_t bubbles_started = 0;      // ... and were played
    std::uint64_t bubbles_dropped = 0;      // ... not played: the pool was full
    std::uint64_t bubbles_above_band = 0;   // ... not played: pitch above the band limit
    std::uint64_t impacts_dropped = 0;      // impact pulses not played: the impact pool was full
};

class WaterSurface {
public:
    explicit WaterSurface(const WaterSurfaceConfig& config = WaterSurfaceConfig{});
    ~WaterSurface();
    WaterSurface(WaterSurface&&) noexcept;
    WaterSurface& operator=(WaterSurface&&) noexcept;
    WaterSurface(const WaterSurface&) = delete;
    WaterSurface& operator=(const WaterSurface&) = delete;

    // A drop lands now: its impact starts with the next sample, and its bubble, if any, too.
    Entrainment strike(double diameter_m, double speed_m_per_s, Random& rng) noexcept;

    double sample() noexcept {
        double x = 0.0;
        process(&x, 1);
        return x;
    }
    void process(double* out, int frames) noexcept;
    void process(float* out, int frames) noexcept;
    void reset() noexcept;   // silence: every bubble and impact stops (stats kept)

    const WaterSurfaceStats& stats() const noexcept { return stats_; }
    int active_bubbles() const noexcept { return active_; }
    int active_impacts() const noexcept;
    const WaterSurfaceConfig& config() const noexcept { return config_; }
    // Pa at 1 m per N/s of dF/dt: (rho_air / rho_w) sin(theta) / (2 pi r c_air).
    double impact_gain() const noexcept { return impact_gain_; }

private:
    static constexpr int scratch_frames = 256;

    WaterSurfaceConfig config_;
    double dt_ = 0.0;
    double impact_gain_ = 0.0;
    std::unique_ptr<ImpactPool> impacts_;
    double previous_force_ = 0.0;
    std::vector<Bubble> bubbles_;   // [0, active_) ringing, in the order they started
    int active_ = 0;
    std::vector<double> scratch_;   // for process(float*)
    WaterSurfaceStats stats_;
};

}  // namespace ameoto
