// SPDX-License-Identifier: GPL-3.0-or-later
// engine/render/umbrella_scene.hpp: an umbrella built once (UmbrellaParts) serves every scene, renderer
// and --level auto measurement of the same umbrella, and what it builds is what their own builds give,
// bit for bit; parts built for another umbrella are refused, never used.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "engine/render/level_choice.hpp"
#include "engine/render/renderer.hpp"
#include "engine/render/umbrella_scene.hpp"

using namespace ameoto;

namespace {

// A small umbrella (20 masses a panel), so that its build in air stays cheap under the sanitizers.
RendererConfig small_umbrella(bool air) {
    RendererConfig c = configure_for_scene(RendererConfig{}, *builtin_scene("umbrella"));
    c.canopy.masses_per_panel = 20;
    c.air = air;
    c.seed = 7;
    c.scene.rain.rate_mm_per_h = c.rain_rate_mm_per_h = 30.0;   // enough drops in 0.1 s to reach every tier
    return c;
}

// `frames` samples of a renderer, all channels in order.
std::vector<float> render_frames(Renderer& r, int frames) {
    const int channels = r.config().channels;
    std::vector<std::vector<float>> planar(static_cast<std::size_t>(channels), std::vector<float>(256));
    std::vector<float*> out;
    for (auto& p : planar) out.push_back(p.data());
    std::vector<float> all;
    for (int done = 0; done < frames; done += 256) {
        r.process(256, out.data());
        for (const auto& p : planar) all.insert(all.end(), p.begin(), p.end());
    }
    return all;
}

}  // namespace

TEST_CASE("umbrella scene: built from parts, it is the scene its own build gives, bit for bit, in vacuum and in air") {
    for (const bool air : {false, true}) {
        CAPTURE(air);
        const DropOnCanopyConfig config = Renderer::umbrella_config(small_umbrella(air));
        const UmbrellaParts parts(config);
        UmbrellaScene own(config);
        UmbrellaScene shared(config, parts);
        CHECK(shared.drops.canopy().in_air() == air);
        CHECK(shared.templates.forces == own.templates.forces);
        CHECK(shared.templates.used == own.templates.used);
        CHECK(shared.texture.energy_fs2 == own.texture.energy_fs2);
        CHECK(shared.texture.centre_hz == own.texture.centre_hz);
        CHECK(shared.texture.decay_s == own.texture.decay_s);
        // A 2 mm drop, 50 ms of it at the listener.
        REQUIRE(own.drops.drop(2e-3, 0.0, 0.25, 0.05));
        REQUIRE(shared.drops.drop(2e-3, 0.0, 0.25, 0.05));
        std::vector<float> a(static_cast<std::size_t>(own.drops.config().channels)), b(a.size());
        bool same = true, sounded = false;
        for (int n = 0; n < 2400; ++n) {
            own.drops.process_frame(a.data());
            shared.drops.process_frame(b.data());
            same = same && a == b;
            sounded = sounded || a[0] != 0.0f;
        }
        CHECK(sounded);
        CHECK(same);
    }
}

TEST_CASE("umbrella parts: they fit what the umbrella does not depend on, and refuse every other change") {
    const RendererConfig base = small_umbrella(false);
    const DropOnCanopyConfig config = Renderer::umbrella_config(base);
    const UmbrellaParts parts(config);
    CHECK(parts.fits(config));
    // The measurement's stereo for an Ambisonic stream, another channel count, another output.
    DropOnCanopyConfig other = config;
    other.listener = ListenerStyle::ambix;
    other.channels = 16;
    CHECK(parts.fits(other));
    other.output = SceneOutput::mass_pickup;
    other.channels = 1;
    CHECK(parts.fits(other));
    // What a renderer config changes without touching the umbrella: rain, level, limiter, detail, node.
    RendererConfig unchanged = base;
    unchanged.rain_rate_mm_per_h = 50.0;
    unchanged.level_gain_db = 12.0;
    unchanged.limiter = true;
    unchanged.adaptive_lod = true;
    unchanged.full_drops = 9;
    CHECK(parts.fits(Renderer::umbrella_config(unchanged)));

    // Anything the canopy, the templates or the texture depend on.
    std::vector<DropOnCanopyConfig> refused(12, config);
    refused[0].material.tension *= 1.01;
    refused[1].material.name = "another";
    refused[2].liquid = liquids::milk();
    refused[3].sample_rate = 44100.0;
    refused[4].geometry.panels = 6;
    refused[5].geometry.curvature_radius_m = 1.0;
    refused[6].air = true;
    refused[7].impact = ImpactModel::seed;
    refused[8].listener_below_m = 0.4;   // the texture is calibrated at the listener
    refused[9].full_scale_pa = 50.0;
    refused[10].network.integrator = Integrator::modal;
    refused[11].settle = false;
    for (std::size_t k = 0; k < refused.size(); ++k) {
        CAPTURE(k);
        CHECK_FALSE(parts.fits(refused[k]));
        CHECK_THROWS_AS(UmbrellaScene(refused[k], parts), std::invalid_argument);
    }
    RendererConfig heavier = base;
    heavier.liquid = liquids::heavy_oil();
    CHECK_THROWS_AS(Renderer(heavier, &parts), std::invalid_argument);
}

TEST_CASE("renderer: the level measurement and the stream from one umbrella's parts give what two builds give") {
    // As ameotod and render scene start a scene with --level auto: the parts built for the scene at its
    // default rain serve the measurement (which hears an Ambisonic bus as stereo) and the stream.
    for (const bool ambix : {false, true}) {
        CAPTURE(ambix);
        RendererConfig at_default = small_umbrella(false);
        if (ambix) {
            at_default.listener = ListenerStyle::ambix;
            at_default.channels = 9;
        }
        const std::shared_ptr<const UmbrellaParts> parts = Renderer::make_parts(at_default);
        const LevelChoice own = choose_level(at_default, default_target_lufs, 0.5);
        const LevelChoice shared = choose_level(at_default, *parts, default_target_lufs, 0.5);
        CHECK(std::isfinite(own.measured_lufs));
        CHECK(shared.measured_lufs == own.measured_lufs);
        CHECK(shared.gain_db == own.gain_db);

        RendererConfig stream = at_default;
        stream.rain_rate_mm_per_h = 50.0;   // --rain: another rate than the one measured
        stream.level_gain_db = own.gain_db;
        Renderer a(stream), b(stream, parts.get());
        const std::vector<float> x = render_frames(a, 4800), y = render_frames(b, 4800);
        CHECK(b.stats().rain_tiers.full + b.stats().rain_tiers.template_ + b.stats().rain_tiers.texture > 0);
        CHECK(x == y);
    }
}
