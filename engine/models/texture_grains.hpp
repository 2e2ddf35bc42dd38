#pragma once
// The texture level of detail: a drop too faint or too buried to model is a grain of noise with the
// energy, colour and length its template would have had, so dense or distant rain keeps its statistics
// (the Poisson arrivals, the size distribution) at a fraction of the cost.
//
// Interface:
//   TextureCalibration cal = calibrate_texture(scene_config, templates);   // off the audio thread (~0.2 s)
//   cal.energy(D), cal.centre_hz(D), cal.decay_s(D)                        // what a grain of size D carries
//   ---- audio thread: no allocation ----
//   TextureGrains grains(cal, sample_rate);              // fixed pool (construct off the audio thread)
//   bool ok = grains.add(D, V, density, azimuth_rad, channels, rng);   // false: pool full (count it)
//   grains.render(frame, channels, rng);                  // adds this sample of every grain to frame[ch]
//
// Calibration: for sizes on a coarse grid (every fifth template size), the template is replayed once
// into a fresh scene of the same material and geometry, half way out along a panel, and its far-field
// output at the listener (mono) is measured over 50 ms: its energy E (sum of squares, full-scale units),
// its spectral centroid f_c (from the DFT of the output) and its decay time tau (the energy over the peak
// of the 1 ms power envelope: the length of a rectangle holding the same energy). Between grid sizes the
// three are interpolated in log D (the energy as log E: it grows about as D^8).
// A grain: white noise through a resonant band-pass at f_c (RBJ biquad, Q = 1; its noise power gain,
// the energy of its impulse response, is exactly b0 = alpha / (1 + alpha)) under an envelope
// exp(-t / tau), scaled so its expected energy is E times the template's gain squared, (rho/rho_k)^2
// (V/V_k)^4 (D/d_k)^4 (impact_templates.hpp: the force ~ rho V^2 D^2), panned by the drop's azimuth
// (panning.hpp). It ends after 5 tau (energy below e^-10). Independent grains add in power, so a
// texture of many carries the summed energy of their templates, with their colour, but none of their
// phase: the statistics, not the events.

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

TextureCalibration calibrate_texture(const DropOnCanopyConfig& scene, const ImpactTemplateTable& templates);

class TextureGrains {
public:
    static constexpr int capacity = 4096;

    TextureGrains(const TextureCalibration& calibration, double sample_rate);

    bool add(double diameter_m, double speed_m_per_s, double density, double azimuth_rad, int channels, Random& rng);
    void render(float* frame, int channels, Random& rng);
    int active() const { return count_; }
    // A new scene's calibration for grains added from now on (grains already sounding keep theirs).
    void set_calibration(const TextureCalibration& calibration) { calibration_ = &calibration; }

private:
    struct Grain {
        double b0 = 0, b2 = 0, a1 = 0, a2 = 0;   // band-pass (b1 = 0)
        double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
        double amplitude = 0, decay = 1;         // envelope: amplitude *= decay each sample
        int left = 0;
        std::array<float, max_pan_channels> gain{};
    };
    const TextureCalibration* calibration_;
    double sample_rate_;
    std::vector<Grain> grains_;   // sized at construction
    int count_ = 0;
};

}  // namespace ameoto
