// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Damped sinusoids fitted to a real signal in one band by the matrix-pencil method (Hua & Sarkar 1990,
// "Matrix pencil method for estimating parameters of exponentially damped/undamped sinusoids in noise",
// IEEE Trans. ASSP 38(5), 814-824): the air reference's estimator of modes that a window cannot separate
// (close canopy modes 5 % apart in a 100 ms record, where a Hann window is about 20 Hz wide).
//
// Interface (any thread; allocates, for offline analysis only):
//   PencilSettings s;  s.f_lo_hz = 100.0;  s.f_hi_hz = 500.0;  s.start_s = 2e-4;
//   std::vector<DampedSinusoid> c = fit_damped_sinusoids(samples, dt, s);   // throws std::invalid_argument
//   c[i].frequency_hz, c[i].damping_per_s, c[i].amplitude, c[i].phase_rad  // x = A e^(-s t) cos(w t + phi)
//   double e = record_energy(c[i], record_s);        // integral of its square over [0, record_s]
//   double f = energy_weighted_frequency(c, record_s);   // Hz: sum e_i f_i / sum e_i
//
// Method. The band [f_lo, f_hi] is mixed down to zero (x_n e^(-i w_c n dt), w_c its centre), low-passed
// by a Kaiser-windowed sinc (pass band the half-width h, stop band from h + t, t = max(h, 4 (A - 8) /
// (2.285 2 pi record)) so that the filter spans at most a quarter of the record; A = stopband_db), and
// decimated to a complex rate of oversampling x 2 (h + t). The filter is applied where it lies wholly on
// the signal ("valid" samples only), so a sum of exponentials z_i^n stays exactly one: each output is
// sum_i c_i H(z_i w) (z_i w)^(n D), with H the filter's transfer function at that (damped) pole; nothing
// of the signal's start is lost to a filter transient, only the last filter length. On the K decimated
// samples the Hankel matrix Y ((K - L) x (L + 1), L = K / 3: Hua & Sarkar's best noise figure lies between
// K / 3 and K / 2) is cut by its SVD, Y = U S V^H, to its M singular values above relative_threshold of
// the largest (at most max_components, at most L); with V1, V2 the first and last L rows of V's first M
// columns, the poles p_i are the eigenvalues of V2^H (V1^H)^+ (Hua & Sarkar eq. 23 in the SVD form of their
// section IV), and the amplitudes the least-squares fit of sum b_i p_i^k to the samples; c_i = b_i / H.
// The components returned are those whose frequency lies in [f_lo, f_hi], sorted by frequency; t = 0 at
// the first sample used (start_s). Each component of a real signal is one pole of the analytic band
// (its negative frequency is filtered out), so a pencil of M poles holds M sinusoids.

#include <vector>

namespace ameoto::reference {

struct DampedSinusoid {
    double frequency_hz = 0.0;
    double damping_per_s = 0.0;    // s in e^(-s t); negative for a growing one (noise, or a poor fit)
    double amplitude = 0.0;        // of the real signal, in its units
    double phase_rad = 0.0;        // at t = 0 (the first sample used)
};

struct PencilSettings {
    double f_lo_hz = 0.0, f_hi_hz = 0.0;   // the band; 0 < f_lo < f_hi < the Nyquist frequency
    double start_s = 0.0;                  // samples before this time are left out (a strike, a transient)
    int max_components = 40;
    double relative_threshold = 1e-5;      // singular values at or below this share of the largest are noise
    double stopband_db = 80.0;             // the low-pass's attenuation outside the band and its transition
    double oversampling = 2.0;             // the decimated rate against the least that keeps the band
};

std::vector<DampedSinusoid> fit_damped_sinusoids(const std::vector<double>& samples, double dt, const PencilSettings& s);

// The integral of A^2 e^(-2 s t) cos^2(w t + phi) over [0, record_s], the cos^2 taken as its mean 1/2
// (exact to 1 / (w record) of it): the component's share of the record's energy.
double record_energy(const DampedSinusoid& c, double record_s);

// The components' frequencies weighted by record_energy: Hz; 0 for none.
double energy_weighted_frequency(const std::vector<DampedSinusoid>& components, double record_s);

}  // namespace ameoto::reference
