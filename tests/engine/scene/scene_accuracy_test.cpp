// SPDX-License-Identifier: GPL-3.0-or-later
// The scene file's accuracy line (format version 2): parsed, validated, written back, and version 1
// files still load (and are still written as version 1 when they need nothing new).
#include <doctest/doctest.h>

#include <string>

#include "engine/scene/scene_description.hpp"
#include "tests/engine/scene/scene_test_support.hpp"

using ameoto::test::error_of;
using namespace ameoto;

namespace {

const std::string umbrella_line = "surface umbrella kind=umbrella material=nylon size=1 x=0 y=0 z=1.9\n";

}  // namespace

TEST_CASE("scene accuracy: version 2 files carry an accuracy budget in cents or dB") {
    SceneDescription s = parse_scene("ameoto-scene 2\nname a\naccuracy cents=5\n" + umbrella_line, "a.scene");
    REQUIRE(s.accuracy);
    CHECK(s.accuracy->measure == AccuracyMeasure::cents);
    CHECK(s.accuracy->value == 5.0);
    s = parse_scene("ameoto-scene 2\naccuracy db=0.5\n", "b.scene");
    REQUIRE(s.accuracy);
    CHECK(s.accuracy->measure == AccuracyMeasure::decibels);
    CHECK(s.accuracy->value == 0.5);
    // Round trip: written as version 2 (it needs it), read back equal.
    const std::string text = format_scene(s);
    CHECK(text.rfind("ameoto-scene 2\n", 0) == 0);
    CHECK(text.find("accuracy db=0.5\n") != std::string::npos);
    CHECK(parse_scene(text, "again.scene") == s);
}

TEST_CASE("scene accuracy: version 1 files still load, and a scene without accuracy is written as version 1") {
    const SceneDescription s = parse_scene("ameoto-scene 1\nname old\n" + umbrella_line, "old.scene");
    CHECK_FALSE(s.accuracy);
    CHECK(format_scene(s).rfind("ameoto-scene 1\n", 0) == 0);
    CHECK(parse_scene("ameoto-scene 2\nname new\n", "new.scene").name == "new");
    for (const std::string& name : builtin_scene_names()) CHECK(format_scene(*builtin_scene(name)).rfind("ameoto-scene 1\n", 0) == 0);
}

TEST_CASE("scene accuracy: errors name the line and the key") {
    CHECK(error_of("ameoto-scene 1\naccuracy cents=5\n") ==
          "test.scene:2: accuracy: the accuracy line needs version 2 (start the file with 'ameoto-scene 2')");
    CHECK(error_of("ameoto-scene 2\naccuracy\n") ==
          "test.scene:2: accuracy: give one of cents=C (frequency error) or db=D (spectral distance)");
    CHECK(error_of("ameoto-scene 2\naccuracy cents=5 db=1\n") ==
          "test.scene:2: accuracy: give one of cents=C (frequency error) or db=D (spectral distance)");
    CHECK(error_of("ameoto-scene 2\naccuracy cents=0\n") == "test.scene:2: cents: 0 cents is outside 0.001..1200");
    CHECK(error_of("ameoto-scene 2\naccuracy db=100\n") == "test.scene:2: db: 100 dB is outside 0.001..60");
    CHECK(error_of("ameoto-scene 2\naccuracy cents=5 colour=red\n") == "test.scene:2: colour: unknown key for 'accuracy'");
    CHECK(error_of("ameoto-scene 2\naccuracy cents=5\naccuracy cents=6\n") == "test.scene:3: accuracy: given twice");
    SceneDescription bad = *builtin_scene("umbrella");
    bad.accuracy = AccuracyBudget{AccuracyMeasure::cents, -1.0};
    CHECK(validate_scene(bad) == "accuracy budget must be 0.001 to 1200 cents");
}
