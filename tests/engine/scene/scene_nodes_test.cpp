// SPDX-License-Identifier: GPL-3.0-or-later
// The scene file's node key on surfaces (format version 3): parsed, validated, written back, and scenes
// on one node are still written in the version they need otherwise.
#include <doctest/doctest.h>

#include <string>

#include "engine/scene/scene_description.hpp"
#include "tests/engine/scene/scene_test_support.hpp"

using ameoto::test::error_of;
using namespace ameoto;

namespace {

const std::string two_nodes = "ameoto-scene 3\nname split\n"
                              "surface umbrella kind=umbrella material=nylon size=1 x=0 y=0 z=1.9\n"
                              "surface car kind=plate material=car-roof size=1.2x1 x=2.5 y=-1.5 z=1.4 node=2\n"
                              "surface puddle kind=water material=puddle size=1x0.8 x=1 y=1 z=0 node=1\n";

}  // namespace

TEST_CASE("scene nodes: version 3 files give surfaces to nodes; the default is node 1") {
    const SceneDescription s = parse_scene(two_nodes, "split.scene");
    REQUIRE(s.surfaces.size() == 3);
    CHECK(s.surfaces[0].node == 1);
    CHECK(s.surfaces[1].node == 2);
    CHECK(s.surfaces[2].node == 1);
    // Round trip: written as version 3 (it needs it), node= only where it is not 1, read back equal.
    const std::string text = format_scene(s);
    CHECK(text.rfind("ameoto-scene 3\n", 0) == 0);
    CHECK(text.find("z=1.4 node=2\n") != std::string::npos);
    CHECK(text.find("node=1") == std::string::npos);
    CHECK(parse_scene(text, "again.scene") == s);
    // All on node 1: nothing new is needed, so the version stays what the rest needs.
    SceneDescription one = s;
    one.surfaces[1].node = 1;
    CHECK(format_scene(one).rfind("ameoto-scene 1\n", 0) == 0);
    for (const std::string& name : builtin_scene_names()) {
        const SceneDescription builtin = *builtin_scene(name);
        for (const SurfaceDescription& f : builtin.surfaces) CHECK(f.node == 1);
    }
}

TEST_CASE("scene nodes: errors name the line and the key") {
    const std::string plate = "surface car kind=plate material=tin size=1 z=2 ";
    CHECK(error_of("ameoto-scene 2\n" + plate + "node=2\n") ==
          "test.scene:2: node: the node key needs version 3 (start the file with 'ameoto-scene 3')");
    CHECK(error_of("ameoto-scene 3\n" + plate + "node=0\n") == "test.scene:2: node: 0 is outside 1..16");
    CHECK(error_of("ameoto-scene 3\n" + plate + "node=17\n") == "test.scene:2: node: 17 is outside 1..16");
    CHECK(error_of("ameoto-scene 3\n" + plate + "node=1.5\n") == "test.scene:2: node: is not a whole number");
    CHECK(error_of("ameoto-scene 3\n" + plate + "node=two\n") == "test.scene:2: node: 'two' is not a number");
    CHECK(error_of("ameoto-scene 3\n" + plate + "node=2 node=3\n") == "test.scene:2: node: given twice");
    CHECK(error_of("ameoto-scene 3\n" + plate + "node=16\n").empty());
    SceneDescription bad = *builtin_scene("street");
    bad.surfaces[1].node = 0;
    CHECK(validate_scene(bad) == "surface 'car': node 0 is outside 1..16");
}
