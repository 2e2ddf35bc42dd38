// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The street scene in two parts for the node tests (ameotod --node K, docs/nodes.md): its car and window on
// node 2, the umbrella and the puddle on node 1 (the default). Written to a file by each test.

namespace ameoto::test {

inline constexpr const char* street_split_scene =
    "ameoto-scene 3\n"
    "name street-split\n"
    "rain rate=10\n"
    "surface umbrella kind=umbrella material=nylon size=1 z=1.9\n"
    "surface car kind=plate material=car-roof size=1.2x1 x=2.5 y=-1.5 z=1.4 node=2\n"
    "surface window kind=plate material=glass size=0.8x0.6 x=-2 y=2 z=1 node=2\n"
    "surface puddle kind=water material=puddle size=1x0.8 x=1 y=1 z=0\n";

}  // namespace ameoto::test
