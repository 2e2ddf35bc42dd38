// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto render scene`'s level (docs/loudness.md): --level physical is the engine's physical output bit for
// bit; --level auto chooses its gain from the scene's default rain, so --rain keeps the physical slope; the
// WAV's comment states the calibration; the printed loudness is the file's.
#include "clients/ameoto/render_scene.hpp"

#include <doctest/doctest.h>
#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/render_drop.hpp"
#include "engine/render/loudness.hpp"
#include "engine/render/renderer.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace ameoto::client;

namespace {

struct RenderedScene {
    std::string out;
    std::vector<float> samples;   // interleaved
    std::string comment;
};

RenderedScene render_scene_wav(std::vector<std::string> words, const std::string& name) {
    const std::string path = ameoto::test::temp_path(name);
    words.insert(words.begin(), "scene");
    words.insert(words.end(), {"--quiet", "-o", path});
    std::ostringstream out, err;
    const CommandIo io{{}, out, err};
    REQUIRE_MESSAGE(run_render(words, io) == exit_status::ok, err.str());
    RenderedScene r;
    r.out = out.str();
    const auto w = ameoto::test::read_wav(path);
    REQUIRE(w.ok);
    r.samples = w.samples;
    SF_INFO info{};
    SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
    REQUIRE(f);
    if (const char* c = sf_get_string(f, SF_STR_COMMENT)) r.comment = c;
    sf_close(f);
    return r;
}

// Any level: the tin roof's physical level (about -80 LUFS) is under the -70 LUFS gate (loudness.hpp).
double scene_lufs(const std::vector<float>& interleaved) { return ameoto::integrated_lufs_any_level(interleaved, 2, 48000.0); }

}  // namespace

TEST_CASE("render scene --level physical: the engine's physical samples, bit for bit, and the calibration in the WAV") {
    const RenderedScene r = render_scene_wav({"--scene", "tin-roof", "--seconds", "0.5", "--level", "physical"}, "physical.wav");
    ameoto::RendererConfig base;
    base.seed = 1;   // render scene's default
    ameoto::Renderer engine(ameoto::configure_for_scene(base, *ameoto::builtin_scene("tin-roof")));
    std::vector<float> left(24000), right(24000);
    float* outs[2] = {left.data(), right.data()};
    engine.process(24000, outs);
    REQUIRE(r.samples.size() == 48000);
    bool same = true;
    for (std::size_t n = 0; n < 24000; ++n) same = same && r.samples[2 * n] == left[n] && r.samples[2 * n + 1] == right[n];
    CHECK(same);
    CHECK(r.comment.find("level physical (1.0 = 100 Pa at the listener)") != std::string::npos);
    CHECK(r.comment.find("0 dBFS = 133.98 dB SPL") != std::string::npos);
    CHECK(r.out.find("limiter off") != std::string::npos);
}

TEST_CASE("render scene --level auto: the gain of the default rain, whatever --rain plays; the slope stays physical") {
    // The tin roof (default 20 mm/h) at 20 and at 60 mm/h, auto without the limiter and physical: the same
    // difference of loudness, to 0.01 LU (a linear gain, chosen once: float rounding only).
    const std::vector<std::string> common{"--scene", "tin-roof", "--seconds", "2", "--limiter", "off"};
    auto with = [&](std::vector<std::string> more) {
        std::vector<std::string> w = common;
        w.insert(w.end(), more.begin(), more.end());
        return w;
    };
    const RenderedScene auto_light = render_scene_wav(with({"--rain", "20"}), "auto-20.wav");
    const RenderedScene auto_heavy = render_scene_wav(with({"--rain", "60"}), "auto-60.wav");
    const RenderedScene phys_light = render_scene_wav(with({"--rain", "20", "--level", "physical"}), "phys-20.wav");
    const RenderedScene phys_heavy = render_scene_wav(with({"--rain", "60", "--level", "physical"}), "phys-60.wav");
    const double auto_slope = scene_lufs(auto_heavy.samples) - scene_lufs(auto_light.samples);
    const double physical_slope = scene_lufs(phys_heavy.samples) - scene_lufs(phys_light.samples);
    MESSAGE("tin roof 20 -> 60 mm/h: " << physical_slope << " LU physical, " << auto_slope << " LU with level auto");
    CHECK(physical_slope > 3.0);   // heavier rain is louder
    CHECK(auto_slope == doctest::Approx(physical_slope).epsilon(0.01 / physical_slope));
    // The same level gain in both auto renders, stated in the comment; the light one lands near -23 LUFS
    // (the first 2 s of the rain the gain was measured on: the level choice renders 3 s of the same seed).
    const auto gain_of = [](const std::string& comment) { return comment.substr(comment.find("level gain"), 20); };
    CHECK(gain_of(auto_light.comment) == gain_of(auto_heavy.comment));
    CHECK(std::fabs(scene_lufs(auto_light.samples) + 23.0) < 1.0);
    CHECK(auto_light.out.find("loudness ") != std::string::npos);
    CHECK(auto_light.out.find("LUFS integrated") != std::string::npos);
}

TEST_CASE("render scene --format binaural: the limiter holds the two ears under its ceiling; --limiter off leaves them over it") {
    // Heavy rain on the tin roof (0.4 s) at the physical scale +78 dB (about 20 dB over --level auto's gain, without
    // its 3 s measurement, for the test's cost): the decoded ears peak well over full scale
    // unlimited. The limiter (engine/render/output_stage.hpp) acts on the ears, after the decode
    // (render_output.hpp): sample peak at or under -1 dBFS by construction, true peak within 0.05 dB of it
    // (the tolerance of output_stage_test.cpp's true-peak case: libebur128's meter against the stage's
    // interpolation of the same filter).
    const std::vector<std::string> loud = {"--scene", "tin-roof", "--format", "binaural", "--rain", "100", "--level", "physical", "--gain", "78",
                                           "--seconds", "0.4"};
    auto with = [&](const std::vector<std::string>& more) {
        std::vector<std::string> w = loud;
        w.insert(w.end(), more.begin(), more.end());
        return w;
    };
    const RenderedScene on = render_scene_wav(with({"--limiter", "on"}), "binaural-limited.wav");
    const RenderedScene off = render_scene_wav(with({"--limiter", "off"}), "binaural-unlimited.wav");
    auto peaks = [](const std::vector<float>& x, double& sample_db, double& true_db) {
        ameoto::LoudnessMeter meter(2, 48000.0, ameoto::LoudnessMeter::peaks);
        meter.add(x.data(), x.size() / 2);
        sample_db = meter.sample_peak_dbfs();
        true_db = meter.true_peak_dbfs();
    };
    double on_sample = 0, on_true = 0, off_sample = 0, off_true = 0;
    peaks(on.samples, on_sample, on_true);
    peaks(off.samples, off_sample, off_true);
    MESSAGE("binaural tin roof, 100 mm/h, physical +78 dB: ears " << off_sample << " dBFS sample peak (" << off_true << " dBTP) unlimited; limited "
                                                         << on_sample << " dBFS (" << on_true << " dBTP)");
    float largest = 0.0f;
    for (const float s : on.samples) largest = std::max(largest, std::fabs(s));
    CHECK(largest <= static_cast<float>(std::pow(10.0, -1.0 / 20.0)));
    CHECK(on_true <= -1.0 + 0.05);
    CHECK(off_sample > 0.0);          // unlimited, the ears pass full scale: the limiter had work to do
    CHECK(on_sample > -1.5);          // limited to the ceiling, not far under it
    CHECK(on.comment.find("limiter on") != std::string::npos);
    CHECK(on.out.find(", 0 samples past full scale") != std::string::npos);    // counted on the ears, not the bus
    CHECK(off.out.find(", 0 samples past full scale") == std::string::npos);
    CHECK(off.comment.find("limiter off") != std::string::npos);
}
