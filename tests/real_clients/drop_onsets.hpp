// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The frames at which separate drops start in a rendered stream, for timing tests.
//
// Interface:
//   std::vector<long long> onsets = drop_onsets(wav, 0.02, 2000);
//   DaemonProcess d({"--scene", sharp_onset_scene(), ...});   // the umbrella in vacuum, written once
//
// An onset is the first frame whose largest absolute sample over the channels exceeds `threshold`
// after at least `gap` frames that did not. A drop on the umbrella rises from below 1e-3 to about
// 0.12 in one frame (a 3 mm drop at terminal speed, 0.2 m from the shaft; the ringing of one 0.25 s
// earlier is below 2e-3 by then), so with the threshold between the two the onset of identical
// drops falls on the same frame of each: their spacing is exact.

#include <string>
#include <vector>

#include "tests/support/wav_file.hpp"

namespace ameoto::test {

std::vector<long long> drop_onsets(const WavData& wav, float threshold, long long gap);

// A scene file (in the test's temporary folder) of the built-in umbrella with its canopy in vacuum
// (`air=off`, the seed's baffled canopy), named whatever the default becomes. The clients' timing tests
// hold the protocol's timing, not the canopy: in air the canopy still rings from the drop before (its
// modes lose 1.6-5.4 /s) and a drop peaks 4.8 dB lower at the listener (docs/canopy-air.md), so onsets
// found by a threshold would move by a few samples and the examples' drops might not cross it.
std::string sharp_onset_scene();

}  // namespace ameoto::test
