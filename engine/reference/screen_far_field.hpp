// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Listening beyond the reference's box (engine/reference/canopy_in_air.hpp), and the band levels the
// fast model is held to with.
//
// Interface:
//   std::vector<double> p = double_layer_pressure(forces, positions, normals, dt, x, c, samples);
//                             // Pa at x, sample n at time (n + 1) dt, from each node's force on the air
//   std::vector<BandLevel> b = third_octave_levels(p, dt, 63.0, 4000.0);   // dB re 1 Pa^2 s per band
//   third_octave_levels(p, dt, 63.0, 4000.0, BandFilter::iec61260)        // through class-1 band filters
//
// The pressure of a thin screen anywhere in free air is its double layer (Kirchhoff-Helmholtz over the
// two faces: Pierce, Acoustics, 1989, section 4.3): node i's pressure jump times its area is the force
// F_i it puts on the air, and each radiates as a point force (Dowling & Ffowcs Williams, Sound and
// Sources of Sound, 1983, section 2.6):
//   p(x, t) = sum_i cos(theta_i) / (4 pi) [ F_i'(t - r_i / c) / (c r_i) + F_i(t - r_i / c) / r_i^2 ],
// cos(theta_i) = (x - y_i) . n_i / r_i. Given the reference's own forces (its FDTD pressure jump, with
// the air's compressibility), this is the reference's field at any distance, exact up to the node-size
// lumping of the faces (so valid for wavelengths of a few node spacings and points a few spacings away:
// tests/engine/models/air_canopy_test.cpp compares it with the box's own pressure at 0.3 m). Retarded
// values by linear interpolation, F' by central differences; before the first sample F = 0.
// Band levels: third-octave bands of nominal centre 1000 * 2^(k/3) Hz and edges centre * 2^(+-1/6)
// (IEC 61260-1's base-2 bands), X the signal's Fourier transform (the rectangular window of the whole
// record: both models are cut at the same time), each band's energy one of
//   ideal:    2 integral |X(f)|^2 df between its edges, X evaluated every 1 / (4 N dt) Hz (a brick wall:
//             a resonance on an edge falls wholly on one side of it);
//   iec61260: 2 integral |X(f)|^2 |H(f)|^2 df, H the band's filter as a third-octave analyser builds it
//             (IEC 61260-1:2014, class 1): a 3rd-order Butterworth band-pass with its -3 dB points on the
//             band's edges, |H|^2 = 1 / (1 + (Q (f/fm - fm/f))^6), Q = 1 / (2^(1/6) - 2^(-1/6)) (the
//             design ANSI S1.11-2004 describes and analysers such as Couvreur's oct3dsgn realise; it
//             meets class 1's mask). A resonance on an edge is half in each band, as an instrument
//             reads it. X from one zero-padded FFT (bins at most 1 / (4 N dt) apart), the filter
//             summed from fm / 4 to 4 fm (past 70 dB down).

#include <vector>

#include "engine/core/body3d_vec3.hpp"

namespace ameoto::reference {

std::vector<double> double_layer_pressure(const std::vector<std::vector<double>>& force_on_air, const std::vector<Vec3>& positions,
                                          const std::vector<Vec3>& normals, double dt, Vec3 x, double speed_of_sound, int samples);

struct BandLevel {
    double centre_hz = 0.0;
    double level_db = 0.0;   // 10 log10(energy / 1 Pa^2 s)
};
enum class BandFilter { ideal, iec61260 };
std::vector<BandLevel> third_octave_levels(const std::vector<double>& signal, double dt, double lo_hz, double hi_hz,
                                           BandFilter filter = BandFilter::ideal);
// |H(f)|^2 of the iec61260 band of centre `centre_hz` at `f_hz` (1 at the centre, 1/2 on the edges).
double third_octave_filter_power(double centre_hz, double f_hz);

}  // namespace ameoto::reference
