// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// How `ameoto bench accuracy` measures a method's error on a body: against the exact solution (the
// modal integrator with every audible mode, which samples the continuous modes exactly at any step,
// integrators/modal.hpp), by the frequency of the first modes and the log-spectral distance of the
// sound, and how it measures where a method blows up (growth factor against omega_max T).
//
// Interface:
//   TransverseNetwork net = build_network(mesh, setting);   // the panel in that method; guard off
//   AccuracyReference ref = make_reference(mesh, 5000);     // exact: audible modes below 5 kHz, response
//   MethodErrors e = measure_errors(mesh, setting, ref);    // e.cents, e.decibels, e.modes_kept, e.mode_hz
//   double hz = zero_crossing_hz(x, fs);                    // from zero crossings; NaN if < 3
//   double d = log_spectral_distance_db(x, reference, fs);  // dB
//   double g = growth_factor(integrator, omega_max_T);      // per step, on an 8-mass chain
//   double g = theoretical_growth(integrator, omega_max_T)  // the bound the chart draws
//
// Frequencies: each reference mode k is excited alone by the force f_i = m_i phi_ik for one sample (its
// impulse T M phi_k puts velocity T phi_k into mode k only: Phi' M Phi = I, and Rayleigh damping keeps
// the modes apart in every scheme here), and the position of the node where phi_k is largest is
// recorded for 0.2 s, up to where it has decayed to 1e-6 of its peak (beyond, rounding's leakage into
// slower modes could take over); its frequency comes from zero crossings, for the method and for the
// reference alike, so the counter's own bias cancels. The modes: every audible mode (non-zero net-force
// weight) below 5 kHz, the band where a mode's frequency is heard as pitch rather than as colour (the
// default 50-mass panel has all 50 of its modes there, 217 Hz to 1.1 kHz). Error: the largest
// |1200 log2(f / f_ref)| over them; a mode the method does not have (a response under 1e-6 of the
// reference's: modal truncation) is an infinite error.
// Spectral distance: 1 N for one sample at the panel's excitation node; the net force (what the
// renderer radiates) for 16384 samples; D = sqrt(mean over DFT bins 20 Hz..20 kHz of
// (20 log10 |X| / |X_ref|)^2), bins more than 80 dB under the reference's peak left out and |X|
// floored there (so a method that loses a band scores a large, finite distance).
// Growth: a fixed-fixed chain of 8 equal masses (omega_max = 2 sqrt(k/m) sin(8 pi / 18), known in closed
// form), struck at one end, run at the step that gives omega_max T, stability policy none, guard off:
// g = (E_n / E_1)^(1 / (2 (n - 1))) after n = 2000 steps, or when E passes 1e200 (the amplitude factor per
// step of the fastest-growing mode; about 1 when bounded, below 1 when damped numerically).

#include <vector>

#include "clients/ameoto/bench_mesh.hpp"
#include "engine/core/method_choice.hpp"
#include "engine/core/transverse_network.hpp"

namespace ameoto::client {

struct AccuracyReference {
    std::vector<double> mode_hz;               // measured on the exact run
    std::vector<double> mode_peak;             // its largest displacement (m)
    std::vector<std::vector<double>> shapes;   // the forces that excite each mode alone (N)
    std::vector<int> listen;                   // the node recorded per mode
    std::vector<double> response;              // the net force after 1 N for one sample (N)
};

struct MethodErrors {
    double cents = 0.0;
    double decibels = 0.0;
    int sub_steps = 1;
    int modes_kept = 0;   // modal: the modes it runs
    std::vector<double> mode_hz;   // each reference mode's frequency in the method (NaN: left out)
};

constexpr double pitch_band_hz = 5000.0;   // modes heard as pitch (see above)
constexpr long frequency_samples = 9600;   // 0.2 s at 48 kHz
constexpr long response_samples = 16384;

TransverseNetwork build_network(const BenchMesh& mesh, const MethodSetting& setting);
AccuracyReference make_reference(const BenchMesh& mesh, double max_hz);
MethodErrors measure_errors(const BenchMesh& mesh, const MethodSetting& setting, const AccuracyReference& reference);
double zero_crossing_hz(const std::vector<double>& x, double sample_rate);
double log_spectral_distance_db(const std::vector<double>& x, const std::vector<double>& reference, double sample_rate);
double growth_factor(Integrator integrator, double omega_max_t);
double theoretical_growth(Integrator integrator, double omega_max_t);

}  // namespace ameoto::client
