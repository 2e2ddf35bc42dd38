// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_levels: the rates and the least-squares slope; the slopes of the scenes
// against rain rate held against the published ones (shared/reference/acoustics.md, section 4): the tin
// roof within the 12-18 dB per decade that metal roofs show (Furukawa Review 21: about 17 dB per decade
// in natural rain; a manufacturer's field data fit 12 to 18), the others between the 10 dB per decade of
// a fixed mix of drop sizes (Guo & Ffowcs Williams 1991: power linear in rate) and 20 (the pond and the
// forest too, whose large soil and leaf patches lost drops to a hit pool of 256 until it became the
// pulse pool's 2 048: 9.8 and 7.6 dB per decade then, docs/levels.md); and what
// `ameoto bench levels` prints and refuses. The renders are short (3 s measured after 1 s of settling,
// per rate, seed 1): about 17 s of CPU in Release.
#include "clients/ameoto/bench_levels.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "clients/ameoto/bench_command.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "tests/support/sanitizer_bounds.hpp"

using namespace ameoto::client;

namespace {

constexpr double test_seconds = 3.0;

SceneLevels short_run(const std::string& name) {
    const ameoto::SceneDescription scene = *ameoto::builtin_scene(name);
    return measure_scene_levels(scene, level_rates(scene.rain.rate_mm_per_h), test_seconds, 1, 2);
}

void report(const SceneLevels& s) {
    std::ostringstream text;
    text << s.scene.name;
    for (const LevelReading& l : s.levels) text << " " << l.rain_mm_per_h << " mm/h: " << l.laeq_db << " dBA " << l.leq_db << " dB;";
    text << " slope " << s.slope_a_db_per_decade << " (A) " << s.slope_z_db_per_decade << " (Z)";
    MESSAGE(text.str());
}

}  // namespace

TEST_CASE("bench levels: the rates are the scene's default, 25, 50 and 100 mm/h, sorted, without repeats") {
    CHECK(level_rates(20.0) == std::vector<double>{20.0, 25.0, 50.0, 100.0});
    CHECK(level_rates(1.5) == std::vector<double>{1.5, 25.0, 50.0, 100.0});
    CHECK(level_rates(25.0) == std::vector<double>{25.0, 50.0, 100.0});
    CHECK(level_rates(200.0) == std::vector<double>{25.0, 50.0, 100.0, 200.0});
}

TEST_CASE("bench levels: the slope is the least-squares fit of level against log10(rate)") {
    std::vector<LevelReading> levels;
    for (double r : {2.0, 25.0, 50.0, 100.0}) {
        LevelReading l;
        l.rain_mm_per_h = r;
        l.laeq_db = 40.0 + 17.0 * std::log10(r);
        l.leq_db = 50.0 + 10.0 * std::log10(r) + (r == 25.0 ? 1.0 : 0.0);
        levels.push_back(l);
    }
    CHECK(slope_db_per_decade(levels, true) == doctest::Approx(17.0).epsilon(1e-12));
    // One point 1 dB high, by hand: x = log10 r, k = sum (x - mx)(y - my) / sum (x - mx)^2.
    double mx = 0.0;
    for (const LevelReading& l : levels) mx += std::log10(l.rain_mm_per_h) / 4.0;
    double sxx = 0.0;
    for (const LevelReading& l : levels) sxx += std::pow(std::log10(l.rain_mm_per_h) - mx, 2);
    CHECK(slope_db_per_decade(levels, false) == doctest::Approx(10.0 + (std::log10(25.0) - mx) / sxx).epsilon(1e-12));
    CHECK(std::isnan(slope_db_per_decade({levels[0]}, true)));
}

TEST_CASE("bench levels: the tin roof's level rises 12-18 dB per decade of rain rate, as metal roofs do") {
    // An accuracy bound: the measurement itself runs under the sanitizers in the JSON case below.
    if (ameoto::test::stop_here_if_sanitized("the slope is an accuracy bound; the measurement runs under them in the JSON case")) return;
    const SceneLevels s = short_run("tin-roof");
    report(s);
    REQUIRE(s.levels.size() == 4);
    for (const LevelReading& l : s.levels) {
        CHECK(l.finite);
        CHECK(std::isfinite(l.laeq_db));
        // Under a bare sheet the A weighting takes off little: the sound is mostly above 500 Hz.
        CHECK(l.leq_db - l.laeq_db > 0.0);
        CHECK(l.leq_db - l.laeq_db < 6.0);
    }
    for (std::size_t i = 1; i < s.levels.size(); ++i) CHECK(s.levels[i].laeq_db > s.levels[i - 1].laeq_db);
    CHECK(s.slope_a_db_per_decade >= 12.0);
    CHECK(s.slope_a_db_per_decade <= 18.0);
    CHECK(s.slope_z_db_per_decade >= 12.0);
    CHECK(s.slope_z_db_per_decade <= 18.0);
}

TEST_CASE("bench levels: the umbrella's level rises 10-20 dB per decade") {
    // An accuracy bound: the measurement itself runs under the sanitizers in the JSON case below.
    if (ameoto::test::stop_here_if_sanitized("the slope is an accuracy bound; the measurement runs under them in the JSON case")) return;
    // (The street, at 25 mm/h and more, is its umbrella to 0.01 dB: the car roof, window and puddle are far below.)
    for (const char* name : {"umbrella"}) {
        const SceneLevels s = short_run(name);
        report(s);
        CAPTURE(name);
        for (const LevelReading& l : s.levels) CHECK(l.finite);
        CHECK(s.slope_a_db_per_decade >= 10.0);
        CHECK(s.slope_a_db_per_decade <= 20.0);
    }
}

TEST_CASE("bench levels: the forest's level rises 10-20 dB per decade: its ground keeps every drop") {
    // An accuracy bound: the measurement itself runs under the sanitizers in the JSON case below.
    if (ameoto::test::stop_here_if_sanitized("the slope is an accuracy bound; the measurement runs under them in the JSON case")) return;
    // Shorter renders (1 s per rate): its patches take thousands of drops a second, so the level settles
    // fast. The forest's slope was 7.6 with the 256-hit pool (its 9 m^2 floor refused 81 % at 100 mm/h),
    // 11.1 now (5 s, 2026-12-01); the pond's, the other scene with large soil, 9.8 then, 12.8 now (not
    // run here: the forest is the harder case and each scene costs about 10 s of CPU).
    for (const char* name : {"forest"}) {
        const ameoto::SceneDescription scene = *ameoto::builtin_scene(name);
        const SceneLevels s = measure_scene_levels(scene, level_rates(scene.rain.rate_mm_per_h), 1.0, 1, 2);
        report(s);
        CAPTURE(name);
        for (const LevelReading& l : s.levels) CHECK(l.finite);
        CHECK(s.slope_a_db_per_decade >= 10.0);
        CHECK(s.slope_a_db_per_decade <= 20.0);
    }
}

TEST_CASE("bench levels: the command prints one JSON object per scene, and refuses bad options") {
    std::ostringstream out, err;
    const CommandIo io{{}, out, err};
    REQUIRE(run_bench({"levels", "--scene", "pond", "--seconds", "0.2", "--json"}, io) == exit_status::ok);
    const std::string text = out.str();
    CHECK(text.starts_with("{\"scene\":\"pond\""));
    CHECK(text.find("\"rain_mm_per_h\":1.5") != std::string::npos);
    CHECK(text.find("\"rain_mm_per_h\":100") != std::string::npos);
    CHECK(text.find("\"slope_a_db_per_decade\":") != std::string::npos);
    CHECK(text.find("null") == std::string::npos);
    CHECK(std::count(text.begin(), text.end(), '\n') == 1);
    for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
             {"levels", "--scene", "moon"}, {"levels", "--seconds", "0"}, {"levels", "--json", "--markdown"},
             {"levels", "--threads", "1.5"}, {"levels", "--bogus"}}) {
        std::ostringstream o, e;
        CAPTURE(bad[1]);
        CHECK(run_bench(bad, {{}, o, e}) == exit_status::usage);
        CHECK(e.str().find("ameoto bench levels --help") != std::string::npos);
    }
    std::ostringstream o, e;
    CHECK(run_bench({"levels", "--help"}, {{}, o, e}) == exit_status::ok);
    CHECK(o.str().starts_with("usage: ameoto bench levels"));
}
