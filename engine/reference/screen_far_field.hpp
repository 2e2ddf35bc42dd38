// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Listening beyond the reference's box (engine/reference/canopy_in_air.hpp), and the band levels the
// fast model is held to with.
//
// Interface:
//   std::vector<double> p = double_layer_pressure(forces, positions, normals, dt, x, c, samples);
//                             // Pa at x, sample n at time (n + 1) dt, from each node's force on the air
//   std::vector<BandLevel> b = third_octave_levels(p, dt, 63.0, 4000.0);   // dB re 1 Pa^2 s per band
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
// (IEC 61260), each band's energy 2 integral |X(f)|^2 df over its edges, X the signal's Fourier transform
// evaluated every 1 / (4 N dt) Hz (the rectangular window of the whole record: both models are cut at
// the same time).

#include <vector>

#include "engine/core/body3d_vec3.hpp"

namespace ameoto::reference {

std::vector<double> double_layer_pressure(const std::vector<std::vector<double>>& force_on_air, const std::vector<Vec3>& positions,
                                          const std::vector<Vec3>& normals, double dt, Vec3 x, double speed_of_sound, int samples);

struct BandLevel {
    double centre_hz = 0.0;
    double level_db = 0.0;   // 10 log10(energy / 1 Pa^2 s)
};
std::vector<BandLevel> third_octave_levels(const std::vector<double>& signal, double dt, double lo_hz, double hi_hz);

}  // namespace ameoto::reference
