// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto render drop`: option parsing, and the real binary rendering a drop to a WAV and an SVG.
#include "clients/ameoto/render_drop.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/render_scene.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"
#include "tests/support/plate_left_scene.hpp"

using namespace ameoto::client;

namespace {

std::string parse_error(const CommandWords& words) {
    RenderDropOptions o;
    std::string error;
    if (parse_render_drop_options(words, o, error) != RenderParse::error) return "(accepted)";
    return error;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("render drop: options are parsed and checked") {
    RenderDropOptions o;
    std::string error;
    REQUIRE(parse_render_drop_options({"--diameter", "5", "--speed=4.5", "--material", "vinyl", "--liquid", "milk", "--seconds",
                                       "0.5", "--rate", "44100", "--seed", "7", "--x", "0.2", "--y", "-0.1", "--output-kind",
                                       "mass", "--channels", "2", "--coarse-steps", "1", "--impact", "seed", "--quiet", "-o", "a.wav", "--plot", "a.svg"},
                                      o, error) == RenderParse::run);
    CHECK(o.diameter_mm == 5.0);
    CHECK(o.speed_m_per_s == 4.5);
    CHECK(o.material == "vinyl");
    CHECK(o.liquid == "milk");
    CHECK(o.seconds == 0.5);
    CHECK(o.rate == 44100);
    CHECK(o.seed == 7u);
    CHECK(*o.x == 0.2);
    CHECK(*o.y == -0.1);
    CHECK(o.output == ameoto::SceneOutput::mass_pickup);
    CHECK(o.channels == 2);
    CHECK(o.coarse_steps == 1);
    CHECK(o.impact == ameoto::ImpactModel::seed);
    CHECK(o.quiet);
    CHECK(o.wav_path == "a.wav");
    CHECK(o.plot_path == "a.svg");

    RenderDropOptions d;
    REQUIRE(parse_render_drop_options({"--diameter", "3", "-o", "b.wav"}, d, error) == RenderParse::run);
    CHECK(d.speed_m_per_s == 0.0);
    CHECK(d.material == "nylon");
    CHECK(d.liquid == "water");
    CHECK(d.seconds == 1.0);
    CHECK(d.rate == 48000);
    CHECK(d.channels == 1);
    CHECK(d.coarse_steps == 4);
    CHECK(d.impact == ameoto::ImpactModel::wet);   // wet by default (docs/impacts.md)
    CHECK(d.air);                                  // the canopy in air by default (docs/canopy-air.md)
    CHECK(d.output == ameoto::SceneOutput::far_field);
    RenderDropOptions v;
    REQUIRE(parse_render_drop_options({"--diameter", "3", "--air", "off", "-o", "b.wav"}, v, error) == RenderParse::run);
    CHECK_FALSE(v.air);   // the seed's canopy in vacuum
    CHECK(parse_render_drop_options({"--diameter", "3", "--air", "maybe", "-o", "b.wav"}, v, error) == RenderParse::error);
    CHECK(error == "--air: 'maybe' is not on or off");
    CHECK_FALSE(d.x.has_value());
    CHECK(parse_render_drop_options({"--help"}, d, error) == RenderParse::help);
}

TEST_CASE("render drop: usage errors say what is wrong, with units") {
    CHECK(has(parse_error({"-o", "a.wav"}), "--diameter MM is required"));
    CHECK(has(parse_error({"--diameter", "3"}), "-o FILE.wav is required"));
    CHECK(has(parse_error({"--diameter", "9", "-o", "a.wav"}), "9 mm is outside 0.1..8 mm"));
    CHECK(has(parse_error({"--diameter", "three", "-o", "a.wav"}), "not a number"));
    CHECK(has(parse_error({"--diameter"}), "--diameter needs a value"));
    CHECK(has(parse_error({"--diameter", "3", "--speed", "40", "-o", "a.wav"}), "40 m/s is outside 0..30 m/s"));
    CHECK(has(parse_error({"--diameter", "3", "--speed", "0.01", "-o", "a.wav"}), "too slow"));
    CHECK(has(parse_error({"--diameter", "3", "--material", "tin", "-o", "a.wav"}), "unknown material 'tin'"));
    CHECK(has(parse_error({"--diameter", "3", "--liquid", "beer", "-o", "a.wav"}), "unknown liquid 'beer'"));
    CHECK(has(parse_error({"--diameter", "3", "--seconds", "100", "-o", "a.wav"}), "100 s is outside 0.01..60 s"));
    CHECK(has(parse_error({"--diameter", "3", "--rate", "44.1", "-o", "a.wav"}), "8000..192000 Hz"));
    CHECK(has(parse_error({"--diameter", "3", "--rate", "4000", "-o", "a.wav"}), "8000..192000 Hz"));
    CHECK(has(parse_error({"--diameter", "3", "--seed", "-1", "-o", "a.wav"}), "--seed"));
    CHECK(has(parse_error({"--diameter", "3", "--x", "0.2", "-o", "a.wav"}), "give both or neither"));
    CHECK(has(parse_error({"--diameter", "3", "--output-kind", "near", "-o", "a.wav"}), "not far-field or mass"));
    CHECK(has(parse_error({"--diameter", "3", "--channels", "3", "-o", "a.wav"}), "not 1 or 2"));
    for (const char* bad : {"0", "65", "2.5", "-1"})
        CHECK(has(parse_error({"--diameter", "3", "--coarse-steps", bad, "-o", "a.wav"}),
                  "--coarse-steps: '" + std::string(bad) + "' is not a whole number of samples in 1..64"));
    CHECK(has(parse_error({"--diameter", "3", "--impact", "dry", "-o", "a.wav"}), "unknown impact model 'dry' (known: wet, seed)"));
    CHECK(has(parse_error({"--diameter", "3", "--quiet=1", "-o", "a.wav"}), "takes no value"));
    CHECK(has(parse_error({"--diameter", "3", "--loud", "-o", "a.wav"}), "unknown option '--loud'"));
    CHECK(has(parse_error({"--diameter", "3", "extra", "-o", "a.wav"}), "unexpected argument 'extra'"));
}

TEST_CASE("render drop: the subcommand refuses what it cannot render") {
    std::ostringstream out, err;
    const CommandIo io{{}, out, err};
    CHECK(run_render({}, io) == exit_status::usage);
    CHECK(run_render({"rain"}, io) == exit_status::usage);
    CHECK(has(err.str(), "drop, scene or score"));
    CHECK(run_render({"drop", "--diameter", "3", "--x", "2", "--y", "0", "-o", "a.wav"}, io) == exit_status::usage);
    CHECK(has(err.str(), "is not on the canopy"));
    CHECK(run_render({"--help"}, io) == exit_status::ok);
    CHECK(has(out.str(), "--diameter MM"));
}

TEST_CASE("render drop: the real binary renders a 3 mm drop to a WAV and an SVG") {
    ameoto::test::TempDir dir("ameoto-render");
    const std::string wav = (dir.path() / "drop.wav").string(), svg = (dir.path() / "drop.svg").string();
    const auto run = ameoto::test::run_program({AMEOTO_BIN_DIR "/ameoto", "render", "drop", "--diameter", "3", "--seconds", "0.3",
                                                "--x", "0.2", "--y", "0.05", "--channels", "2", "-o", wav, "--plot", svg},
                                               std::chrono::seconds(60));
    INFO(run.out);
    REQUIRE(run.exit_code == 0);
    CHECK(has(run.out, "rendered 0.300 s"));
    CHECK(has(run.out, "pieces at the end"));
    CHECK(has(run.out, "dBFS"));

    const ameoto::test::WavData w = ameoto::test::read_wav(wav);
    REQUIRE(w.ok);
    CHECK(w.is_float);
    CHECK(w.channels == 2);
    CHECK(w.sample_rate == 48000);
    CHECK(w.frames == 14400);
    double peak = 0.0;
    bool finite = true;
    for (float s : w.samples) {
        finite = finite && std::isfinite(s);
        peak = std::max(peak, static_cast<double>(std::fabs(s)));
    }
    CHECK(finite);
    CHECK(peak > 1e-4);

    std::ifstream in(svg);
    std::stringstream text;
    text << in.rdbuf();
    const std::string doc = text.str();
    CHECK(doc.rfind("<?xml", 0) == 0);
    CHECK(has(doc, "</svg>"));
    CHECK(has(doc, "3 mm water drop on nylon"));
    CHECK(has(doc, ">pieces<"));                    // the series
    CHECK(has(doc, "drop masses, side view"));      // the scatter
    CHECK(has(doc, "<circle"));
    CHECK(has(doc, "<path d=\"M"));                 // series and waveform
    CHECK(has(doc, "fill=\"#"));                    // spectrogram cells
}

TEST_CASE("render scene: options are checked, and a built-in scene renders the same samples twice") {
    using ameoto::client::parse_render_scene_options;
    using ameoto::client::RenderSceneOptions;
    RenderSceneOptions o;
    std::string error;
    CHECK(parse_render_scene_options({"--scene", "pond"}, o, error) == RenderParse::error);
    CHECK(error == "-o FILE.wav is required");
    CHECK(parse_render_scene_options({"--scene", "../x", "-o", "a.wav"}, o, error) == RenderParse::error);
    CHECK(has(error, "neither a built-in scene"));
    CHECK(parse_render_scene_options({"--rain", "600", "-o", "a.wav"}, o, error) == RenderParse::error);
    CHECK(has(error, "600 mm/h is outside 0..500 mm/h"));
    CHECK(parse_render_scene_options({"--channels", "17", "-o", "a.wav"}, o, error) == RenderParse::error);
    CHECK(parse_render_scene_options({"--format", "ambix:2", "--channels", "2", "-o", "a.wav"}, o, error) == RenderParse::error);
    CHECK(error == "give --format or --channels, not both (ring:N is N channels)");
    CHECK(parse_render_scene_options({"--format", "ambix:0", "-o", "a.wav"}, o, error) == RenderParse::error);
    CHECK(has(error, "the Ambisonic order is 1, 2 or 3"));
    {
        // ambix:1: 4 channels, and the WAV's comment says what they are.
        const std::string path = ameoto::test::temp_path("scene-ambix.wav");
        std::ostringstream out, err;
        const CommandIo io{{}, out, err};
        REQUIRE(run_render({"scene", "--scene", "pond", "--format", "ambix:1", "--seconds", "0.1", "--quiet", "-o", path}, io) ==
                exit_status::ok);
        const auto w = ameoto::test::read_wav(path);
        REQUIRE(w.ok);
        CHECK(w.channels == 4);
        std::ifstream in(path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        CHECK(has(bytes, "Channels: ambix:1 (AmbiX: ACN order, SN3D, no Condon-Shortley phase): ACN 0 W, ACN 1 Y, ACN 2 Z, ACN 3 X"));
    }
    {
        // binaural: rain on a plate 3 m to the left, decoded through the KEMAR HRIRs: two channels, the
        // left ear louder. 6 dB: the brief's interaural bound above 2 kHz, here over the whole band (the
        // plate's sound is mostly above 2 kHz; the decoder's own test checks the band and the delay).
        const std::string scene = ameoto::test::temp_path("plate-left.scene"), path = ameoto::test::temp_path("scene-binaural.wav");
        std::ofstream(scene) << ameoto::test::plate_left_scene;
        std::ostringstream out, err;
        const CommandIo io{{}, out, err};
        REQUIRE_MESSAGE(run_render({"scene", "--scene", scene, "--format", "binaural", "--level", "physical", "--seconds", "0.3",
                                    "--quiet", "-o", path},
                                   io) == exit_status::ok,
                        err.str());
        const auto w = ameoto::test::read_wav(path);
        REQUIRE(w.ok);
        REQUIRE(w.channels == 2);
        double left = 0.0, right = 0.0;
        for (float v : w.channel(0)) left += static_cast<double>(v) * v;
        for (float v : w.channel(1)) right += static_cast<double>(v) * v;
        INFO("left " << left << ", right " << right);
        REQUIRE(right > 0.0);
        CHECK(10.0 * std::log10(left / right) > 6.0);
    }
    const std::string a = ameoto::test::temp_path("scene-a.wav"), b = ameoto::test::temp_path("scene-b.wav");
    for (const std::string& path : {a, b}) {
        std::ostringstream out, err;
        const CommandIo io{{}, out, err};
        CHECK(run_render({"scene", "--scene", "pond", "--seconds", "0.2", "--quiet", "-o", path}, io) == exit_status::ok);
        CHECK(has(out.str(), "of scene 'pond' at 1.5 mm/h"));
    }
    const auto wa = ameoto::test::read_wav(a), wb = ameoto::test::read_wav(b);
    REQUIRE(wa.ok);
    REQUIRE(wb.ok);
    CHECK(wa.channels == 2);
    CHECK(wa.frames == 9600);
    CHECK(wa.samples == wb.samples);   // the header has a time stamp; the audio is the same
    double peak = 0.0;
    for (float v : wa.samples) peak = std::max(peak, static_cast<double>(std::abs(v)));
    CHECK(peak > 0.0);
}
