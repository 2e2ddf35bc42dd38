// SPDX-License-Identifier: GPL-3.0-or-later
// --format and the scene file's `output format=`: parsing, channel counts and labels.

#include <doctest/doctest.h>

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene/output_format.hpp"
#include "engine/scene/scene_description.hpp"

TEST_CASE("output format: every format parses to its channels and back to its name") {
    std::string error;
    for (const auto& [text, channels] : std::initializer_list<std::pair<std::string, int>>{
             {"stereo", 2}, {"ears", 2}, {"ring:1", 1}, {"ring:6", 6}, {"ring:16", 16}, {"ambix:1", 4}, {"ambix:2", 9}, {"ambix:3", 16}, {"binaural", 2}}) {
        CAPTURE(text);
        const auto f = ameoto::parse_output_format(text, error);
        REQUIRE(f);
        CHECK(f->channels == channels);
        CHECK(f->name() == text);
        CHECK(ameoto::output_channel_names(*f).size() == static_cast<std::size_t>(channels));
    }
    for (const std::string bad : {"ambix:0", "ambix:4", "ambix:", "ring:0", "ring:17", "ring:2x", "quad", "", "Stereo"}) {
        CAPTURE(bad);
        CHECK(!ameoto::parse_output_format(bad, error));
        CHECK(!error.empty());
    }
    CHECK(error == "'Stereo' is not an output format (stereo, ears, ring:N (1..16), ambix:ORDER (1..3) or binaural)");
    const auto ambix = ameoto::parse_output_format("ambix:1", error);
    CHECK(ameoto::output_channel_summary(*ambix) ==
          "ambix:1 (AmbiX: ACN order, SN3D, no Condon-Shortley phase): ACN 0 W, ACN 1 Y, ACN 2 Z, ACN 3 X");
    const auto ring = ameoto::parse_output_format("ring:4", error);
    CHECK(ameoto::output_channel_names(*ring) ==
          std::vector<std::string>{"ring 1 az +45 deg", "ring 2 az -45 deg", "ring 3 az -135 deg", "ring 4 az +135 deg"});
    CHECK(ameoto::output_format_for_channels(2).name() == "stereo");
    CHECK(ameoto::output_format_for_channels(5).name() == "ring:5");
}

TEST_CASE("output format: the scene file's output format= key (version 4)") {
    const std::string body = "name fmt\noutput format=ambix:2\n";
    const ameoto::SceneDescription s = ameoto::parse_scene("ameoto-scene 4\n" + body, "f.scene");
    CHECK(s.output_format == "ambix:2");
    CHECK(ameoto::parse_scene(ameoto::format_scene(s), "again") == s);
    CHECK(ameoto::format_scene(s).rfind("ameoto-scene 4\n", 0) == 0);
    auto error_of = [](const std::string& text) {
        try {
            ameoto::parse_scene(text, "f.scene");
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(error_of("ameoto-scene 3\n" + body) == "f.scene:3: format: the format key needs version 4 (start the file with 'ameoto-scene 4')");
    CHECK(error_of("ameoto-scene 4\nname fmt\noutput format=ambix:5\n") ==
          "f.scene:3: format: 'ambix:5': the Ambisonic order is 1, 2 or 3 (ambix:ORDER: 4, 9 or 16 channels)");
}
