// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One air bubble ringing under a water surface, as heard in the air above it: Minnaert's pitch, van den
// Doel's damping and rising chirp, and the pressure its pulsation radiates through the surface.
//
// Interface:
//   double f = minnaert_frequency_hz(a);          // f0 = (1 / 2 pi a) sqrt(3 gamma P0 / rho), Hz
//   double d = bubble_damping_per_s(a);           // van den Doel: 0.13 / a + 0.0072 a^(-3/2), 1/s
//   double p = bubble_pressure_amplitude_pa(a);   // initial amplitude, Pa at 1 m in air (below)
//   Bubble b;                                     // idle; holds no memory of its own
//   bool ok = b.start(a, p, sample_rate_hz);      // false (stays idle) if its pitch is at or above
//                                                 // bubble::band_limit of the sample rate
//   double x = b.sample();                        // next sample, Pa; 0 once finished
//   b.render_add(out, frames);                    // adds the next `frames` samples to out[]
//   b.active(); b.remaining_samples();            // still ringing; samples left
// All members are noexcept, allocate nothing and take no locks: safe on the audio thread.
// Radii are in m (SI): a = 0.22e-3 is the 0.22 mm bubble of light rain.
//
// Signal (van den Doel, "Physically based models for liquid sounds", ACM TAP 2(4), 2005; physics.md 4):
//   p(t) = P e^(-d t) sin(phi(t)),  phi(t) = 2 pi f0 (t + xi d t^2 / 2),  i.e. f(t) = f0 (1 + xi d t),
// with xi = 0.1 (the rising pitch of a bubble moving away from the surface after pinch-off). It starts at
// p = 0: a bubble that started at a crest would begin with a step, a broadband click this model does
// not claim. Pitch: Minnaert (1933) with gamma = 1.4 (adiabatic air) and P0 = 101325 Pa, about 3.29 / a
// Hz; neglected here, each worth under a few per cent: surface tension (+0.25 % at 0.22 mm), the
// thermal (polytropic) correction of small bubbles (lower), and the image in the free surface (higher).
// Damping: van den Doel's fit to the thermal, viscous and radiation losses of Devin (1959), amplitude
// decay rate d in 1/s, a in m: 2797 / 904 / 358 1/s at a = 0.22 / 0.5 / 1 mm (physics.md 4).
//
// Level (bubble_pressure_amplitude_pa). A pulsating bubble a little below the surface drives the surface
// itself: for a bubble within a wavelength of the surface the water is incompressible around it, so the
// surface above moves out with the bubble's whole volume velocity Q = 4 pi a^2 eps', spread over a patch
// about as wide as the bubble is deep. Phillips, Agarwal & Jordan (Sci. Rep. 8:9515, 2018) showed that
// this piston, not sound crossing the water-air interface (a -65 dB path), is what we hear in the air.
// Seen from the air the water is rigid (impedance ratio about 3600), so the patch is a baffled monopole
// (Rayleigh integral, Kinsler et al. 4th ed. 7.4) as long as it is small against the air wavelength:
//   p(r) = rho_air Q' / (2 pi r) = 2 rho_air a^2 eps'' / r  ->  amplitude 2 rho_air w0^2 a^2 eps0 / r
//        = 2 rho_air (3 gamma P0 / rho_w) eps0 / r          (w0 a is Minnaert's constant),
// the same in every direction over the water (the patch, a few mm across, is compact below 20 kHz).
// eps0, the initial wall displacement: Pumphrey & Crum (JASA 87:142, 1990) found it small (linear
// oscillation); we take eps0 = 1 % of the radius for the 0.22 mm bubble of light rain (ASSUMPTION: an
// order of magnitude, consistent with the Pa-level pressures measured a few cm from such bubbles
// underwater, Yang et al., arXiv:2512.09336, 2025) and scale it as a^(3/2), which makes the radiated
// amplitude van den Doel's A a^(3/2) with A = 2 rho_air (3 gamma P0 / rho_w) eps0(a_ref) a_ref^(-3/2):
// P = 2.26 mPa at 1 m for a = 0.22 mm (41 dB SPL peak), 7.7 mPa at 0.5 mm, 21.9 mPa at 1 mm. The pressure is p = -2 rho_air a^2 eps'' / r to within d / w0
// (3-6 %): the damping's and chirp's own derivatives are dropped, so the waveform is the sine above.
//
// Band limit: a bubble whose pitch is at or above bubble::band_limit (0.45) of the sample rate is not
// started (it would alias); one that chirps up to that limit fades out by 60 dB before 0.49 of the
// sample rate (an extra exponential decay from the moment it crosses 0.45). At 96 kHz no bubble of rain
// is refused (13-25 kHz; the 25 kHz one reaches 43.2 kHz already 63 dB down); at 48 kHz those above
// 21.6 kHz are not played.
//
// Recursion: p[n] = Im z[n] with z[n+1] = z[n] w[n], w[n+1] = w[n] c, z[0] = P, w[0] = e^(-d T + i D0),
// c = e^(i w0 xi d T^2): the phase increment phi[n+1] - phi[n] = w0 T + w0 xi d T^2 (n + 1/2) grows by a
// constant, so two complex products per sample give the sampled formula exactly, up to rounding (relative
// error about n^2 * 1e-16, 1e-8 over a 10 000-sample life), at a fraction of the cost of sin and exp.
// A bubble ends when its envelope is 80 dB below its start (bubble::cutoff).

#include <cmath>

namespace ameoto {

namespace bubble {
inline constexpr double adiabatic_index = 1.4;            // gamma of air (physics.md 4, Minnaert)
inline constexpr double ambient_pressure_pa = 101325.0;   // P0, one standard atmosphere (physics.md 4: 101.3 kPa)
inline constexpr double chirp_xi = 0.1;                   // van den Doel 2005 (physics.md 4: xi ~ 0.1)
inline constexpr double reference_radius_m = 0.22e-3;     // the light-rain bubble (Pumphrey, Crum & Bjorno 1989)
inline constexpr double reference_relative_amplitude = 0.01;   // eps0 / a at the reference radius (assumption, above)
inline constexpr double reference_distance_m = 1.0;       // where bubble_pressure_amplitude_pa is given
inline constexpr double band_limit = 0.45;                // of the sample rate: highest pitch played
inline constexpr double fade_end = 0.49;                  // of the sample rate: 60 dB down by this pitch
inline constexpr double cutoff = 1e-4;                    // envelope at which a bubble ends (-80 dB)
}  // namespace bubble

double minnaert_frequency_hz(double radius_m);
double bubble_damping_per_s(double radius_m);
double bubble_pressure_amplitude_pa(double radius_m);

class Bubble {
public:
    // (Re)starts this bubble: radius (m), initial amplitude (Pa), sample rate (Hz), chirp xi (>= 0).
    // Returns false, and leaves the bubble idle, for a non-positive or non-finite argument or a pitch at
    // or above bubble::band_limit * sample_rate_hz.
    bool start(double radius_m, double amplitude_pa, double sample_rate_hz, double xi = bubble::chirp_xi) noexcept;

    double sample() noexcept {
        double x = 0.0;
        render_add(&x, 1);
        return x;
    }
    void render_add(double* out, int frames) noexcept;
    void stop() noexcept { remaining_ = 0; }

    bool active() const noexcept { return remaining_ > 0; }
    long remaining_samples() const noexcept { return remaining_; }
    double radius_m() const noexcept { return radius_; }
    double frequency_hz() const noexcept { return frequency_; }   // f0, at the start
    double damping_per_s() const noexcept { return damping_; }
    double amplitude_pa() const noexcept { return amplitude_; }

private:
    double zr_ = 0.0, zi_ = 0.0;   // P e^(-d t) e^(i phi)
    double wr_ = 0.0, wi_ = 0.0;   // per-sample factor, decay folded in
    double cr_ = 1.0, ci_ = 0.0;   // chirp rotation
    double fade_ = 1.0;            // extra per-sample decay once the pitch reaches the band limit
    long remaining_ = 0;           // samples left
    long until_fade_ = -1;         // samples before the fade starts; -1: never
    double radius_ = 0.0, frequency_ = 0.0, damping_ = 0.0, amplitude_ = 0.0;
};

}  // namespace ameoto
