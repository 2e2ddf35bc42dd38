// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The canopy in air in the frequency domain: its sound at listening points per newton on one node, with
// the air's mass given at each frequency (the incompressible M_a of air_loading.hpp, or the compressible
// M_a(omega) of air_loading_helmholtz.hpp). For telling apart, band by band, what the air's
// compressibility changes in the fast model's sound (docs/canopy-air.md). Offline; allocates.
//
// Interface:
//   AirMassAt air = compressible_air_mass(canopy, rho0, c, step_hz);   // M_a(omega), interpolated
//   AirMassAt flat = incompressible_air_mass(canopy, rho0);             // M_a(0) at every frequency
//   CanopyFrequencyResponse r = canopy_frequency_response(canopy, panel, node, listeners, hz, air, c);
//   r.pressure[l][f]          // Pa per N at listener l, frequency hz[f] (e^(i omega t))
//   std::vector<std::complex<double>> F = canopy_air_forces(canopy, panel, node, hz, air);   // per node
//   directional_force(canopy, F, k, theta, psi)   // what the far field towards (theta, psi) hears
//   raised_cosine_spectrum(peak_n, length_s, hz)          // S(f) of the reference's strike
//   canopy_time_response(canopy, panel, node, listeners, air, c)   // [listener][sample], Pa: the strike
//                                                          // heard over the reference's 0.2 s record
//
// The canopy's equation of motion at frequency omega, (K + i omega C - omega^2 (M + M_a(omega))) u = f,
// is block circulant over the panels (K, C, M the lattice's, one panel's copied; M_a air_loading's), so
// it is solved on the panels' Fourier modes, one panel's size each. The air takes F = -omega^2 M_a u,
// heard as the fast model hears it (dipole_radiation.hpp): each node a point force on the air,
// p = sum_i cos(theta_i) / (4 pi) e^(-ik r_i) (1 / r_i^2 + i k / r_i) F_i.

#include <complex>
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/body3d_vec3.hpp"

namespace ameoto {
class Canopy;
}

namespace ameoto::reference {

// The air's mass on the panels' Fourier modes at omega (rad/s): [m], nodes x nodes, kg.
using AirMassAt = std::function<std::vector<Eigen::MatrixXcd>(double omega)>;

// Computed at multiples of step_hz (cached) and interpolated linearly between (50 Hz: within 0.3 % of the
// exact M_a at 2-4 kHz, the test). The canopy must outlive the function.
AirMassAt compressible_air_mass(const Canopy& canopy, double air_density, double speed_of_sound, double step_hz);
AirMassAt incompressible_air_mass(const Canopy& canopy, double air_density);

struct CanopyFrequencyResponse {
    std::vector<double> hz;
    std::vector<std::vector<std::complex<double>>> pressure;   // [listener][frequency], Pa / N
};

// The force each node puts on the air per newton on (panel, node) at hz: F = -omega^2 M_a u, panel-major.
// Throws std::invalid_argument for a node out of range.
std::vector<std::complex<double>> canopy_air_forces(const Canopy& canopy, int panel, int node, double hz, const AirMassAt& air);

// The forces' far-field sum towards the direction (theta from the canopy's axis, azimuth psi) at wave
// number k: S = sum_i F_i e^(i k sin(theta) (cos(psi) x_i + sin(psi) y_i)), N per N. A flat screen's far
// field there is i k cos(theta) e^(-ikR) S / (4 pi R) (dipole_radiation.hpp).
std::complex<double> directional_force(const Canopy& canopy, const std::vector<std::complex<double>>& forces, double k, double theta,
                                       double psi);

// Throws std::invalid_argument for a node out of range or no listener.
CanopyFrequencyResponse canopy_frequency_response(const Canopy& canopy, int panel, int node, const std::vector<Vec3>& listeners,
                                                  const std::vector<double>& hz, const AirMassAt& air, double speed_of_sound);

// The spectrum of a raised-cosine force pulse (peak_n (1 - cos(2 pi t / length)) / 2 over 0..length),
// integral f(t) e^(-i omega t) dt, N s; and its Laplace transform at any s.
std::complex<double> raised_cosine_spectrum(double peak_n, double length_s, double hz);
std::complex<double> raised_cosine_laplace(double peak_n, double length_s, std::complex<double> s);

// The model's pressure in time after a raised-cosine strike, for band levels over the same record as the
// reference's (its modes ring past the record: a steady spectrum would not do). The Laplace transform is
// taken on the line Re s = sigma at the frequencies k / period up to max_hz (nothing above) and inverted
// (synthesize): the period's wrapped tail is e^(-sigma period) of it (-70 dB by default). Pa, sample n at
// time n / rate_hz.
struct CanopyTimeResponseSetup {
    double duration_s = 0.2, rate_hz = 48000.0, max_hz = 4600.0;
    double period_s = 0.5, sigma = 16.0;   // 1/s
    double force_n = 1.0, pulse_s = 2e-4;
};
std::vector<std::vector<double>> canopy_time_response(const Canopy& canopy, int panel, int node, const std::vector<Vec3>& listeners,
                                                      const AirMassAt& air, double speed_of_sound,
                                                      const CanopyTimeResponseSetup& setup = {});
// x(t) from X(sigma + i 2 pi k / period), k = 0..K (the rest conjugate or zero): samples n / rate_hz.
std::vector<double> synthesize(const std::vector<std::complex<double>>& laplace, double sigma, double period_s, double rate_hz, int samples);

}  // namespace ameoto::reference
