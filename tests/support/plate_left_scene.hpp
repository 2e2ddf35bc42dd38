// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The direction tests' scene: rain (20 mm/h) on a 1 m x 1 m tin plate 3 m to the listener's left, at the
// ears' height, and no umbrella, so that nothing else is heard. The Ambisonic intensity vector, the
// binaural ears, AmbDec's speakers and the head's turns are all read on it. A scene file's text: write it
// to a file for ameotod or ameoto, or parse_scene() it for the renderer.

namespace ameoto::test {

inline constexpr const char* plate_left_scene =
    "ameoto-scene 1\n"
    "name plateleft\n"
    "rain rate=20\n"
    "listener x=0 y=0 z=1.6 facing=0\n"
    "surface plate kind=plate material=tin size=1x1 x=0 y=3 z=1.6\n";

}  // namespace ameoto::test
