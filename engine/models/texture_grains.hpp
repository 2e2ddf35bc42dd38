// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The texture level of detail: a drop too faint or too buried to model is a grain of noise with the
// energy, colour and length its template would have had, so dense or distant rain keeps its statistics
// (the Poisson arrivals, the size distribution) at a fraction of the cost.
//
// Interface:
//   TextureCalibration cal = calibrate_texture(scene_config, templates);   // off the audio thread (~0.1 s)
//   cal.energy(D), cal.centre_hz(D), cal.decay_s(D)                        // what a grain of size D carries
//   ---- audio thread: no allocation ----
//   TextureGrains grains(cal, sample_rate);              // the noise bed (construct off the audio thread)
//   bool ok = grains.add(D, V, density, azimuth_rad, channels, rng);   // false: no calibration
//   grains.render(frame, channels, rng);                  // adds this sample of the bed to frame[ch]
//
// Calibration: for sizes on a coarse grid (every fifth template size), the template is replayed once
// into a fresh scene (its canopy copied from one built once per call) of the same material and
// geometry, half way out along a panel, and its far-field output at the listener (mono) is measured
// over 50 ms: its energy E (sum of squares, full-scale units), its spectral centroid f_c (from the DFT
// of the output) and its decay time tau (the energy over the peak of the 1 ms power envelope: the length
// of a rectangle holding the same energy). Between grid sizes they are interpolated in log D (the energy
// as log E: it grows about as D^8).
// The bed: grains are not rendered one by one (that would cost more than replaying their templates).
// Each channel has 12 noise bands, log-spaced from 150 Hz to 16 kHz (at most 0.4 fs), each white noise
// through a constant-peak band-pass (RBJ biquad, Q = sqrt(r) / (r - 1) for the bands' ratio r, so
// neighbours cross at -3 dB), normalised to unit variance (the noise power gain of that band-pass, the
// energy of its impulse response, is exactly b0 = alpha / (1 + alpha)), scaled by the square root of the
// band's power envelope P. P decays as exp(-2 t / tau_b), tau_b the calibrated decay at the band's
// centre. A grain of energy E (its size's, times the template's gain squared, (rho/rho_k)^2 (V/V_k)^4:
// impact_templates.hpp's force ~ rho V^2 D^2) at centre f_c adds to the two bands whose output's power
// centroids c_k, c_k+1 lie around f_c, split linearly in f (t = (f_c - c_k) / (c_k+1 - c_k) to the upper), so
// that the bed's expected power centroid is f_c itself (a band's output is centred above its nominal
// centre by its skirts: 2.0 times at 150 Hz, 1.47 at 1.25 kHz, 1.10 at 6.8 kHz, at 48 kHz; split by the
// nominal centres, the wet impact's lower centroids came out 1.74 times the full tier's in bench
// accuracy), E (1 - d^2) g_c^2 to each channel's P, d = exp(-1 / (tau_b fs)) and g_c its pan
// gain: the bed's expected energy then grows by exactly E. Independent grains add in power, so the bed
// carries the summed energy of their templates with their colour and decay, but none of their phase:
// the statistics, not the events. Cost: 12 band-passes and square roots per channel per sample, whatever
// the number of grains; a grain costs a few multiplications when added.
// active(): grains added within the last 5 tau (the longest band's), a measure for /status.

#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/impact_templates.hpp"
#include "engine/models/panning.hpp"

namespace ameoto {

struct TextureCalibration {
    std::vector<double> diameters_m, energy_fs2, centre_hz, decay_s;   // per calibrated size, ascending D
    std::vector<double> speeds_m_per_s;                                // their arrival speeds
    std::vector<double> log_energy;                                    // ln energy_fs2 (interpolation)
    double density = 998.0;                                            // kg/m^3: the recorded liquid's
    double energy(double diameter_m) const;
    double centre(double diameter_m) const;
    double decay(double diameter_m) const;
    bool empty() const { return diameters_m.empty(); }
};

// build: shared (one canopy per call, copied per size) or per_size (each size builds its own: the same
// calibration bit for bit, slower; tests compare the two).
TextureCalibration calibrate_texture(const DropOnCanopyConfig& scene, const ImpactTemplateTable& templates,
                                     CanopyBuild build = CanopyBuild::shared);
// The same from the caller's canopy, never stepped (record_impact_templates' prototype form).
TextureCalibration calibrate_texture(const DropOnCanopyConfig& scene, const ImpactTemplateTable& templates, const Canopy& prototype);

class TextureGrains {
public:
    static constexpr int bands = 12;

    TextureGrains(const TextureCalibration& calibration, double sample_rate);

    bool add(double diameter_m, double speed_m_per_s, double density, double azimuth_rad, int channels, Random& rng);
    void render(float* frame, int channels, Random& rng);
    int active() const { return active_; }
    // A new scene's calibration for grains added from now on (the bed keeps what it holds).
    void set_calibration(const TextureCalibration& calibration);
    double band_centre_hz(int band) const { return centre_[static_cast<std::size_t>(band)]; }
    // Hz: the power centroid of the band's output (its noise through the band-pass, 0..fs/2), above its
    // centre: the skirts of a two-pole band-pass fall as 1 / f^2, which weighted by f reach far up.
    double band_power_centroid_hz(int band) const { return power_centre_[static_cast<std::size_t>(band)]; }

private:
    struct Band {
        double b0 = 0, b2 = 0, a1 = 0, a2 = 0;   // band-pass (b1 = 0)
        double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
        double power = 0.0;                       // the envelope P
    };
    const TextureCalibration* calibration_;
    double sample_rate_;
    std::array<double, bands> centre_{}, decay_{}, unit_{};   // Hz; per-sample power decay d^2; 1/sqrt(b0/3)
    std::array<double, bands> power_centre_{};                // Hz: each band's output's power centroid
    std::array<std::array<Band, bands>, max_pan_channels> bed_{};
    static constexpr int slot_samples = 64;
    std::vector<int> added_;   // grains added per 64-sample slot, over the last 5 tau (a ring)
    int slot_ = 0, in_slot_ = 0, active_ = 0;
};

}  // namespace ameoto
