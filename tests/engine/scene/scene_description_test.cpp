// SPDX-License-Identifier: GPL-3.0-or-later
// Scene descriptions: built-in scenes, the versioned file format, and its errors (file, line, field).
#include "engine/scene/scene_description.hpp"
#include "tests/engine/scene/scene_test_support.hpp"

using ameoto::test::error_of;
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <algorithm>
#include <string>
#include <vector>

using namespace ameoto;

namespace {

int line_of(const std::string& text) {
    try {
        parse_scene(text, "test.scene");
    } catch (const SceneFileError& e) {
        return e.line();
    }
    return -1;
}

const std::string good = "ameoto-scene 1\n"
                         "# a comment\n"
                         "\n"
                         "name my-street\n"
                         "rain rate=12.5 dsd=joss-thunderstorm wind=4 direction=90 gust=0.25\n"
                         "listener x=1 y=-2 z=1.7 facing=45\n"
                         "lod budget=40 full=8\n"
                         "surface brolly kind=umbrella material=vinyl size=1.1 z=1.9 panels=6\n"
                         "surface roof kind=plate material=tin size=1x0.6 x=-3 y=2 z=3\n";

}  // namespace

TEST_CASE("scene file: every field reads back in SI units") {
    const SceneDescription s = parse_scene(good, "good.scene");
    CHECK(s.name == "my-street");
    CHECK(s.rain.rate_mm_per_h == 12.5);
    CHECK(s.rain.dsd == "joss-thunderstorm");
    CHECK(s.rain.wind_m_per_s == 4.0);
    CHECK(s.rain.wind_direction_rad == ameoto::test::relative(3.14159265358979 / 2));   // degrees in the file
    CHECK(s.rain.gustiness == 0.25);
    CHECK(s.listener.x_m == 1.0);
    CHECK(s.listener.y_m == -2.0);
    CHECK(s.listener.facing_rad == ameoto::test::relative(3.14159265358979 / 4));
    CHECK(s.lod.budget_percent == 40.0);
    CHECK(s.lod.max_full == 8);
    REQUIRE(s.surfaces.size() == 2);
    CHECK(s.surfaces[0].kind == SurfaceKind::umbrella);
    CHECK(s.surfaces[0].size_x_m == 1.1);
    CHECK(s.surfaces[0].size_y_m == 1.1);   // one size: square (an umbrella's diameter)
    CHECK(s.surfaces[0].panels == 6);
    CHECK(s.surfaces[1].kind == SurfaceKind::plate);
    CHECK(s.surfaces[1].size_x_m == 1.0);
    CHECK(s.surfaces[1].size_y_m == 0.6);
    CHECK(s.surfaces[1].x_m == -3.0);
}

TEST_CASE("scene file: format then parse gives the same scene, for every built-in and a custom one") {
    for (const std::string& name : builtin_scene_names()) {
        CAPTURE(name);
        const auto s = builtin_scene(name);
        REQUIRE(s);
        CHECK(validate_scene(*s) == "");
        CHECK(parse_scene(format_scene(*s), name) == *s);
    }
    SceneDescription custom = parse_scene(good, "good.scene");
    custom.rain.wind_direction_rad = 0.0;   // angles go through degrees: exact only to rounding
    custom.listener.facing_rad = 0.0;
    CHECK(parse_scene(format_scene(custom), "again") == custom);
    custom = parse_scene(good, "good.scene");
    const SceneDescription again = parse_scene(format_scene(custom), "again");
    CHECK(again.rain.wind_direction_rad == ameoto::test::relative(custom.rain.wind_direction_rad).epsilon(1e-15));
    CHECK(!builtin_scene("no-such-scene"));
    CHECK(builtin_scene("umbrella")->surfaces.size() == 1);
}

TEST_CASE("scene file: errors name the file, the line and the field, and say why") {
    CHECK(error_of("") == "test.scene: empty: no 'ameoto-scene 1' line");
    CHECK(error_of("hello\n").find("not an ameoto scene file") != std::string::npos);
    CHECK(error_of("ameoto-scene 6\n") == "test.scene:1: version: version 6 needs a newer ameoto (this one reads versions 1 to 5)");
    CHECK(error_of("ameoto-scene x\n").find("not a version number") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nrain rate=900\n") == "test.scene:2: rate: 900 mm/h is outside 0..500");
    CHECK(error_of("ameoto-scene 1\nrain rate=abc\n") == "test.scene:2: rate: 'abc' is not a number");
    CHECK(error_of("ameoto-scene 1\nrain rate=5 colour=red\n") == "test.scene:2: colour: unknown key for 'rain'");
    CHECK(error_of("ameoto-scene 1\nrain rate=5 rate=6\n") == "test.scene:2: rate: given twice");
    CHECK(error_of("ameoto-scene 1\nrain rate=5\nrain rate=6\n") == "test.scene:3: rain: given twice");
    CHECK(error_of("ameoto-scene 1\nrain rate=nan\n").find("outside") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nrain rate=inf\n").find("outside") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nrain dsd=hail\n").find("dsd: 'hail' is not one of") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nweather sunny\n").find("unknown line") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nrain rate\n") == "test.scene:2: rate: expected key=value");
    CHECK(error_of("ameoto-scene 1\nsurface a kind=plate material=tin\n") == "test.scene:2: size: missing (surface needs it)");
    CHECK(error_of("ameoto-scene 1\nsurface a kind=plate material=gold size=1\n").find("material 'gold' is not one of tin, glass, car-roof") !=
          std::string::npos);
    CHECK(error_of("ameoto-scene 1\nsurface a kind=lake material=pond size=1\n").find("kind: 'lake' is not one of") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nsurface ../etc kind=water material=pond size=1\n").find("is not 1-32 of") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nsurface a kind=water material=pond size=1\nsurface a kind=water material=pond size=1\n")
              .find("a second surface named 'a'") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nsurface a kind=umbrella material=nylon size=1\nsurface b kind=umbrella material=nylon size=1\n")
              .find("at most one umbrella") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nsurface a kind=water material=pond size=1x\n").find("size: '' is not a number") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\nlod full=2.5\n") == "test.scene:2: full: is not a whole number of drops");
    // The line number counts comments and blank lines.
    CHECK(line_of("# c\n\nameoto-scene 1\n\n# c\nrain rate=-1\n") == 6);
}

TEST_CASE("scene file: size limits, line endings and binary junk") {
    std::string many = "ameoto-scene 1\n";
    for (int i = 0; i <= max_scene_surfaces; ++i)
        many += "surface s" + std::to_string(i) + " kind=water material=pond size=1\n";
    CHECK(error_of(many).find("more than 16 surfaces") != std::string::npos);
    CHECK(error_of("ameoto-scene 1\n# " + std::string(2000, 'x') + "\n").find("line longer than 1024") != std::string::npos);
    CHECK(error_of(std::string(70000, '#')).find("larger than 64 KiB") != std::string::npos);
    CHECK(error_of(std::string("ameoto-scene 1\nname a\0b\n", 23)).find("NUL") != std::string::npos);
    // Windows line endings and a missing final newline are fine.
    const SceneDescription s = parse_scene("ameoto-scene 1\r\nname crlf\r\nrain rate=3", "crlf.scene");
    CHECK(s.name == "crlf");
    CHECK(s.rain.rate_mm_per_h == 3.0);
}

TEST_CASE("scene names are names, never paths") {
    CHECK(is_scene_name("tin-roof"));
    CHECK(is_scene_name("My_Scene2"));
    for (const char* bad : {"", "../x", "/etc/passwd", "a/b", ".", "..", "a b", "x.scene", "\xc3\xa9t\xc3\xa9"}) {
        CAPTURE(bad);
        CHECK_FALSE(is_scene_name(bad));
    }
    CHECK_FALSE(is_scene_name(std::string(33, 'a')));
}

TEST_CASE("scene file: cut at every byte, or with any byte changed, reads or fails with the file and a line in it, "
          "never anything else") {
    // Every built-in scene as written, and the hand-written one: each prefix (a truncated write or
    // copy) and each single-byte change (to NUL, '=', a space, 0xff) either is a valid scene or throws
    // SceneFileError naming the file and a line that exists.
    std::vector<std::string> texts{good};
    for (const std::string& name : builtin_scene_names()) texts.push_back(format_scene(*builtin_scene(name)));
    int refused = 0, read = 0;
    for (const std::string& text : texts) {
        const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
        auto check = [&](const std::string& variant) {
            try {
                const SceneDescription s = parse_scene(variant, "cut.scene");
                CHECK(validate_scene(s).empty());
                ++read;
            } catch (const SceneFileError& e) {
                CHECK(std::string(e.what()).rfind("cut.scene", 0) == 0);
                CHECK(e.line() >= 0);
                CHECK(e.line() <= lines);
                ++refused;
            }
        };
        for (std::size_t n = 0; n < text.size(); ++n) check(text.substr(0, n));
        for (std::size_t i = 0; i < text.size(); ++i)
            for (const char c : {'\0', '=', ' ', '\xff'}) {
                std::string v = text;
                v[i] = c;
                check(v);
            }
    }
    MESSAGE(read << " variants read, " << refused << " refused");
    CHECK(refused > 1000);
}

TEST_CASE("scene file: numbers too large for a double, too many keys, and a version far in the future are refused") {
    CHECK(error_of("ameoto-scene 1\nrain rate=1e400\n").rfind("test.scene:2: rate: ", 0) == 0);
    CHECK(error_of("ameoto-scene 1\nlistener x=-1e400\n").rfind("test.scene:2: x: ", 0) == 0);
    CHECK(error_of("ameoto-scene 1\nlod full=99999999999999999999\n").rfind("test.scene:2: full: ", 0) == 0);
    CHECK(error_of("ameoto-scene 99999999999999999999\n").rfind("test.scene:1: ", 0) == 0);
    CHECK(error_of("ameoto-scene 0\n").rfind("test.scene:1: version: ", 0) == 0);
    CHECK(error_of("ameoto-scene -1\n").rfind("test.scene:1: ", 0) == 0);
    std::string keys = "ameoto-scene 1\nrain";
    for (int i = 0; i < 100; ++i) keys += " k" + std::to_string(i) + "=1";
    CHECK(error_of(keys + "\n").rfind("test.scene:2: k0: unknown key", 0) == 0);
    // A name longer than 32 characters, in the file.
    CHECK(error_of("ameoto-scene 1\nname " + std::string(40, 'a') + "\n").rfind("test.scene:2: ", 0) == 0);
}

TEST_CASE("scene file: a subnormal value format_scene writes reads back (found by the fuzzer)") {
    SceneDescription s = *builtin_scene("umbrella");
    s.listener.x_m = 9.33678148025e-313;
    s.surfaces.at(0).x_m = 9.33678148025e-313;
    REQUIRE(validate_scene(s).empty());
    CHECK(parse_scene(format_scene(s), "tiny.scene") == s);
    CHECK(error_of("ameoto-scene 1\nrain rate=1e400\n") == "test.scene:2: rate: inf mm/h is outside 0..500");
    CHECK(error_of("ameoto-scene 1\nrain rate=1x\n") == "test.scene:2: rate: '1x' is not a number");
}

TEST_CASE("scene file: the umbrella's air key: on, off (the default before version 5, on from 5), anything else refused with its line") {
    const std::string head = "ameoto-scene 1\nsurface u kind=umbrella material=nylon size=1 z=1.9";
    CHECK_FALSE(parse_scene(head + "\n", "test.scene").surfaces[0].air);
    // The default: off in versions 1-4 (a file made before keeps its sound), on from version 5.
    for (int version = 1; version <= 5; ++version) {
        const std::string v = "ameoto-scene " + std::to_string(version) + "\nsurface u kind=umbrella material=nylon size=1 z=1.9";
        CHECK(parse_scene(v + "\n", "test.scene").surfaces[0].air == (version >= 5));
        CHECK(parse_scene(v + " air=on\n", "test.scene").surfaces[0].air);
        CHECK_FALSE(parse_scene(v + " air=off\n", "test.scene").surfaces[0].air);
    }
    // The built-in scenes' umbrellas are in air, and a saved copy keeps them there (written as version 1).
    for (const std::string name : {"umbrella", "street"}) {
        const SceneDescription b = *builtin_scene(name);
        CHECK(b.surfaces[0].kind == SurfaceKind::umbrella);
        CHECK(b.surfaces[0].air);
        CHECK(format_scene(b).rfind("ameoto-scene 1\n", 0) == 0);
        CHECK(parse_scene(format_scene(b), "saved.scene") == b);
    }
    CHECK(parse_scene(head + " air=on\n", "test.scene").surfaces[0].air);
    CHECK_FALSE(parse_scene(head + " air=off\n", "test.scene").surfaces[0].air);
    CHECK(error_of(head + " air=yes\n") == "test.scene:2: air: 'yes' is not on or off");
    CHECK(error_of("ameoto-scene 1\nsurface w kind=water material=pond size=1 air=on\n") == "test.scene:2: air: unknown key for 'surface'");
    // format_scene writes it when on, and it reads back.
    SceneDescription s = parse_scene(head + " air=on\n", "test.scene");
    CHECK(format_scene(s).find(" air=on") != std::string::npos);
    CHECK(parse_scene(format_scene(s), "again.scene") == s);
    s.surfaces[0].air = false;
    CHECK(format_scene(s).find("air=") == std::string::npos);
}

TEST_CASE("scene file: the umbrella's impact key: wet (the default), seed, anything else refused with its line") {
    const std::string head = "ameoto-scene 1\nsurface u kind=umbrella material=nylon size=1 z=1.9";
    CHECK(parse_scene(head + "\n", "test.scene").surfaces[0].impact == ImpactModel::wet);
    CHECK(parse_scene(head + " impact=seed\n", "test.scene").surfaces[0].impact == ImpactModel::seed);
    CHECK(parse_scene(head + " impact=wet\n", "test.scene").surfaces[0].impact == ImpactModel::wet);
    CHECK(error_of(head + " impact=elastic\n") == "test.scene:2: impact: 'elastic' is not wet or seed");
    CHECK(error_of("ameoto-scene 1\nsurface p kind=plate material=tin size=1 impact=seed\n") ==
          "test.scene:2: impact: unknown key for 'surface'");
    // format_scene writes it when it is not the default, and it reads back.
    SceneDescription s = parse_scene(head + " impact=seed\n", "test.scene");
    CHECK(format_scene(s).find(" impact=seed") != std::string::npos);
    CHECK(parse_scene(format_scene(s), "again.scene") == s);
    s.surfaces[0].impact = ImpactModel::wet;
    CHECK(format_scene(s).find("impact=") == std::string::npos);
}
