// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Sound from one source to the listener through open air: spherical spreading, the propagation delay and
// air absorption, all following the source's and the listener's positions smoothly.
//
// Interface:
//   Propagation path(PropagationConfig{.sample_rate = 48000, .max_distance_m = 200});   // allocates
//                                         // (delay line, filter taps; the air fit is cached per climate)
//   path.set_positions_now(listener, source);   // jump there (a scene's initial state); default 0 -> (1,0,0)
//   path.set_listener(p); path.set_source(p);  // targets: the distance glides there linearly in glide_s
//   double y = path.process(x);                 // one sample; no allocation, no locks
//   path.process(in, out);                      // a block (spans of equal size; may alias)
//   path.distance(), path.gain(), path.delay_samples()   // current values (they glide)
//   path.air_attenuation_db(r, f_hz)            // the realised air filter's attenuation at distance r
//   path.reset();                               // silence the delay line and filter
//   iso9613_attenuation_db_per_m(f_hz, t_c, rh_pct, p_kpa)   // ISO 9613-1 eq. (5), dB/m
//   speed_of_sound_m_per_s(t_c)                 // 343 sqrt(T / 293.15 K)
// One Propagation per source; a listener that moves is set on each.
//
// Spreading: pressure gain 1 / r relative to the level at 1 m (a point source in free field), r floored at
// min_distance_m (0.1 m: at most +20 dB). No ground reflection, no directivity, no wind or temperature
// gradients (ISO 9613-2's other terms are left to the scene).
// Delay: r / c samples, c = 343.0 sqrt(T / 293.15 K) (the engine's 343 m/s at 20 C, scaled as an ideal gas).
// The delay line is read by windowed-sinc interpolation (J. O. Smith, "Digital Audio Resampling Home
// Page", CCRMA, bandlimited interpolation: 32 taps, Kaiser window beta = 8, a table of 256 fractional
// phases interpolated linearly, each phase normalised to unit DC gain): exact at integer delays, and at
// half a sample within 0.002 dB of that up to 16 kHz and 0.003 dB up to 20 kHz at 48 kHz (tested), where
// a linear or cubic Lagrange read would lose 6 or 3 dB at 16 kHz. Its latency plus the air filter's is
// the shortest delay a path can give: 15 + K samples (K below; 35 samples = 0.73 ms at 48 kHz with
// max_distance 200 m), so a source nearer than that c-distance (25 cm) is heard that late; the gain
// still follows r.
// Air absorption (ISO 9613-1:1993, eq. (3)-(5); a test checks the formula against ISO 9613-2:1996,
// Table 2): the attenuation r alpha(f) dB is realised as a linear-phase FIR, a mix of two sampled
// Gaussians, (1 - beta) G(sigma_a) + beta G(sigma_b), sigma_a <= sigma_b <= 3 sigma_a (in samples; taps
// exp(-k^2 / 2 sigma^2) - e^-8, clipped at 0, normalised to unit DC gain: continuous in sigma, 2 K + 1
// taps, K = floor(4 sigma_b) at the largest distance: 20 at 48 kHz for 200 m, 47 for 1 km). Why this
// shape: below the oxygen relaxation (52 kHz at 20 C, 70 %) alpha grows as f^2, which is the attenuation
// in dB of a Gaussian; the nitrogen relaxation (460 Hz) adds a shelf, which the wider Gaussian's share
// beta gives. The three parameters are fitted per distance by least squares in dB over the 1/3-octave
// centres 50 Hz..20 kHz (up to 0.45 fs), each side saturated at 60 dB (deeper is inaudible, and a
// Gaussian cannot follow it forever), by Nelder-Mead at construction (13 ms for 200 m at 48 kHz, once
// per climate, rate and range: cached for the process), at 0.5 m and then 3 distances per octave up to
// max_distance, interpolated linearly in ln r (sigma ~ sqrt(r) below 0.5 m, so below about 0.3 m, where
// ISO gives under 0.1 dB, the taps vanish). Linear phase: the filter adds exactly K samples, which the
// delay line subtracts, so the delay is right at every frequency. Fit error, max over the bands (20 C,
// 70 %, 48 kHz): 0.05 dB at 1 m, 0.30 dB at 10 m (at 20 kHz), 0.24 dB at 30 m, 0.36 dB at 100 m, 0.73 dB
// at 300 m; the realised filter at 1, 4, 8, 16 kHz is within 0.17 dB at 10 m and 0.35 dB at 100 m
// (tested to 0.5 dB). Other climates at 100 m: 0.24 dB (10 C, 70 %), 0.69 dB (0 C, 90 %), 1.5 dB in
// dry air (20 C, 20 %, where the oxygen relaxation falls in band).
// Cost: about 60 ns per sample at rest (K = 20), 200 ns while the distance glides (taps recomputed).
// Smooth changes (no zipper noise): a new position sets a target distance; the current distance glides to
// it linearly in glide_s (20 ms; a new target restarts the glide from where it is), and the gain, the
// fractional delay and the filter's taps are recomputed from it every sample while it moves: all are
// continuous in r. A moving delay is a Doppler shift, the physical one for a source sent its positions
// continuously; a jump of d metres is heard as a glide at d / glide_s m/s.
// Distances beyond max_distance_m are clamped there for the delay and the filter (the gain keeps 1 / r).

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "engine/core/body3d_vec3.hpp"

namespace ameoto {

struct PropagationConfig {
    double sample_rate = 48000.0;
    double max_distance_m = 200.0;       // sizes the delay line and the filter
    double temperature_c = 20.0;
    double relative_humidity_pct = 70.0;
    double pressure_kpa = 101.325;
    double glide_s = 0.02;               // a position change takes this long to be heard in full
    double min_distance_m = 0.1;         // the 1 / r gain is held below it
};

// ISO 9613-1:1993 eq. (3)-(5): the pure-tone attenuation coefficient alpha, dB per metre.
double iso9613_attenuation_db_per_m(double frequency_hz, double temperature_c, double relative_humidity_pct,
                                    double pressure_kpa = 101.325);
double speed_of_sound_m_per_s(double temperature_c);

class Propagation {
public:
    // Throws std::invalid_argument on a sample rate below 8 kHz, a distance range that is not positive (or
    // beyond 5 km), humidity outside 0..100 %, temperature outside -40..60 C, or a negative glide.
    explicit Propagation(const PropagationConfig& config = {});

    void set_listener(Vec3 position);
    void set_source(Vec3 position);
    void set_positions_now(Vec3 listener, Vec3 source);
    double process(double x);
    void process(std::span<const double> in, std::span<double> out);
    void reset();

    double distance() const { return r_; }
    double target_distance() const { return r_target_; }
    double gain() const { return gain_; }
    double delay_samples() const { return delay_; }
    double min_delay_samples() const;
    int air_filter_half_length() const { return k_max_; }   // K
    double speed_of_sound() const { return c_; }
    double air_attenuation_db(double distance_m, double frequency_hz) const;
    const PropagationConfig& config() const { return config_; }

    // The fitted air filter at one table distance (for docs and tests).
    struct AirFit {
        double distance_m, sigma_a, sigma_b, beta;
    };
    struct AirTable;   // shared between paths with the same climate, rate and range

private:
    void update_from_distance();
    AirFit fit_at(double distance_m) const;

    PropagationConfig config_;
    double c_ = 343.0;
    std::shared_ptr<const AirTable> air_;
    int k_max_ = 0;
    std::vector<double> line_;       // the delay line (power-of-two ring)
    std::size_t line_mask_ = 0, write_ = 0;
    std::vector<double> fir_in_;     // the interpolated signal, the air filter's input (power-of-two ring)
    std::size_t fir_mask_ = 0, fir_write_ = 0;
    std::vector<double> taps_;       // taps_[k], k = 0..K (symmetric)
    std::vector<double> scratch_;    // the second Gaussian's taps while mixing
    Vec3 listener_{}, source_{1.0, 0.0, 0.0};
    double r_ = 1.0, r_target_ = 1.0, glide_step_ = 0.0;
    double gain_ = 1.0, delay_ = 0.0;
    std::size_t read_integer_ = 0;   // delay-line read: integer part and phase position
    double read_phase_ = 0.0;
};

}  // namespace ameoto
