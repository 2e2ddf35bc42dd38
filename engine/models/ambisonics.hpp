// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Ambisonic encoding (AmbiX: ACN channel order, SN3D normalisation, no Condon-Shortley phase) and the
// rotation of an encoded bus, orders 1 to 3 (4, 9 or 16 channels).
//
// Interface:
//   std::array<double, 16> g = ambix_gains(azimuth_rad, elevation_rad, order);   // g[acn], acn < (order+1)^2
//   std::array<double, 16> g = ambix_gains(Vec3 direction, order);               // the same from a vector
//   int n = ambix_channels(order);            // (order + 1)^2
//   int order = ambix_order(channels);        // 1..3 for 4, 9, 16 channels; -1 otherwise
//   std::string s = ambix_channel_name(acn);  // "ACN 0 W", "ACN 1 Y", ... (the FuMa letter where one exists)
//   std::array<double, 16> g = direction_gains(az, el, channels, ambisonic);   // the renderer's one entry:
//                                             // SH gains (ambisonic) or pan_gains(az, channels) (panning.hpp)
//   AmbixRotation r = AmbixRotation::from_orientation(yaw, pitch, roll, order);  // control thread: allocates
//                                             // while it is built (a least-squares fit, Eigen); order 0:
//                                             // W alone, the identity (what a panned stream is sent)
//   r.apply(in, out);                         // any thread, never allocates: out = R in, per order block
//
// Directions: azimuth counter-clockwise from +x (front) towards +y (left), elevation up from the
// horizontal plane, as the renderer's coordinates (x forward, y left, z up).
// Encoding (Nachbar, Zotter, Deleflie & Sontacchi, "AmbiX - a suggested Ambisonics format", Ambisonics
// Symposium 2011; Zotter & Frank, "Ambisonics", Springer 2019, section 4.8): channel acn = n^2 + n + m
// carries
//   Y_n^m(az, el) = N_n^|m| P_n^|m|(sin el) * { cos(m az), m >= 0 ; sin(|m| az), m < 0 },
//   N_n^|m| = sqrt((2 - delta_m0) (n - |m|)! / (n + |m|)!)          (SN3D: W = 1 for every direction)
// with P_n^m the associated Legendre function without the (-1)^m phase. Computed here by the standard
// recurrences of P_n^m (Abramowitz & Stegun 8.5.3 and 8.6.x, phase dropped); the tests check them against
// the closed forms of the published table.
// Rotation: a listener's head turned by H (yaw about z, then pitch, then roll about the new axes) hears a
// source at direction v from direction H^T v. For each order n the functions Y_n^m span a space that
// rotations map into itself, so there is one (2n+1)^2 matrix R_n with Y_n(H^T v) = R_n Y_n(v) for every v
// (Zotter & Frank, section 5.2). It is fitted here by least squares from 64 directions spread over the
// sphere (a Fibonacci lattice: the fit is exact up to rounding because the relation is exact; residual
// under 1e-12, tested), which is simpler than the recurrences of Ivanic & Ruedenberg (J. Phys. Chem. 1996)
// and costs about 0.1 ms, off the audio thread.
// Orientation (head trackers, /listener/orientation): yaw turns the head to the left (counter-clockwise
// seen from above, as azimuth), pitch raises the nose, roll lowers the right ear; degrees at the
// protocol boundary, radians here.

#include <array>
#include <string>

#include "engine/core/body3d_vec3.hpp"

namespace ameoto {

inline constexpr int max_ambix_order = 3;
inline constexpr int max_ambix_channels = 16;

constexpr int ambix_channels(int order) { return (order + 1) * (order + 1); }
int ambix_order(int channels);
std::array<double, max_ambix_channels> ambix_gains(double azimuth_rad, double elevation_rad, int order);
std::array<double, max_ambix_channels> ambix_gains(Vec3 direction, int order);   // any length > 0; 0: W only
std::string ambix_channel_name(int acn);
std::array<double, max_ambix_channels> direction_gains(double azimuth_rad, double elevation_rad, int channels, bool ambisonic);

struct AmbixRotation {
    int order = 1;
    // Row-major (max_ambix_channels x max_ambix_channels), block diagonal: entries outside the order
    // blocks are 0 and never read.
    std::array<double, max_ambix_channels * max_ambix_channels> m{};

    static AmbixRotation identity(int order);
    static AmbixRotation from_orientation(double yaw_rad, double pitch_rad, double roll_rad, int order);
    // out[acn] = sum over the same order's acn' of m[acn][acn'] in[acn']; in and out may not alias.
    void apply(const double* in, double* out) const;
    bool is_identity() const;
    bool operator==(const AmbixRotation&) const = default;
};

// The head's rotation H as a 3x3 matrix (row-major): its columns are the head's front, left and up axes
// in the listener's body frame.
std::array<double, 9> head_rotation(double yaw_rad, double pitch_rad, double roll_rad);

}  // namespace ameoto
