// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Amplitude panning of a source at an azimuth over a ring of loudspeakers, for the renderer's panned
// output (a canopy's panels spread over the speakers by their azimuths).
//
// Interface:
//   std::array<double, max_pan_channels> g = pan_gains(azimuth_rad, channels);   // g[c], sum g^2 = 1
//
// Azimuth: radians, 0 = front (+x), counter-clockwise towards the left (+y), as the canopy's panel
// azimuths. Mono gets 1; stereo is left/right by sin(azimuth) with a constant-power (sine/cosine) law;
// three or more channels are a ring of speakers starting front-left and going clockwise, panned
// pairwise between the two nearest with the same law (Pulkki's VBAP in 2-D reduces to this for a
// regular ring with equal spacing).

#include <array>

namespace ameoto {

inline constexpr int max_pan_channels = 16;

std::array<double, max_pan_channels> pan_gains(double azimuth_rad, int channels);

}  // namespace ameoto
