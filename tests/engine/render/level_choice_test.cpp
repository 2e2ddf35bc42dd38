// SPDX-License-Identifier: GPL-3.0-or-later
// --level auto (engine/render/level_choice.hpp): each built-in scene's default rain, played with the gain
// chosen for it, lands at the target loudness; the choice does not follow the rain actually played (not an
// automatic gain control), so heavier rain stays louder by its physical amount.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "engine/render/level_choice.hpp"
#include "engine/render/loudness.hpp"
#include "engine/render/renderer.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/timing_scale.hpp"

using namespace ameoto;

namespace {

// Integrated loudness (LUFS) of `seconds` of the renderer's output, through its output stage.
double render_lufs(const RendererConfig& config, double seconds) {
    Renderer r(config);
    const int channels = config.channels;
    const int total = static_cast<int>(seconds * config.sample_rate);
    constexpr int block = 1024;
    std::vector<std::vector<float>> planar(static_cast<std::size_t>(channels), std::vector<float>(block));
    std::vector<float*> out;
    for (auto& p : planar) out.push_back(p.data());
    std::vector<float> interleaved(static_cast<std::size_t>(block * channels));
    LoudnessMeter meter(channels, config.sample_rate, LoudnessMeter::integrated);
    for (int done = 0; done < total; done += block) {
        const int n = std::min(block, total - done);
        r.process(n, out.data());
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < channels; ++c)
                interleaved[static_cast<std::size_t>(i * channels + c)] = planar[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
        meter.add(interleaved.data(), static_cast<std::size_t>(n));
    }
    return meter.integrated_lufs();
}

RendererConfig scene_config(const char* name, std::uint64_t seed) {
    RendererConfig base;
    base.seed = seed;
    base.limiter = true;   // as ameotod and render scene run with --level auto
    return configure_for_scene(base, *builtin_scene(name));
}

}  // namespace

TEST_CASE("level auto: every built-in scene at its default rain plays within 1 LU of the target") {
    // As ameotod and render scene do: the gain is chosen from the first 3 s of the stream's own rain (seed 1),
    // then 5 s of that stream are played through the output stage (limiter on): its last 2 s are rain the
    // choice never heard. Tolerance 1 LU: issue 21's bound (measured 2026-12-01: within 0.6 LU for every
    // scene, docs/loudness.md). Another seed's rain is louder or quieter by itself: the umbrella's 12 s
    // integrated loudness is -48.15, -47.13 and -48.73 LUFS for seeds 1, 2 and 3 (render scene --level physical).
    for (const std::string& name : builtin_scene_names()) {
        // Under the sanitizers the umbrella alone (a canopy, the texture grains and the limiter): each scene
        // costs 30-60 s there, and the surfaces' sources run under them in level_rate_test.cpp.
        if (ameoto::test::sanitized_build() && name != "umbrella") continue;
        RendererConfig config = scene_config(name.c_str(), 1);
        const LevelChoice choice = choose_level(config, default_target_lufs);
        REQUIRE(std::isfinite(choice.measured_lufs));
        config.level_gain_db = choice.gain_db;
        const double played = render_lufs(config, 5.0);
        MESSAGE(name << ": default rain " << config.scene.rain.rate_mm_per_h << " mm/h measures " << choice.measured_lufs
                     << " LUFS physical; level gain " << choice.gain_db << " dB; played (5 s) " << played << " LUFS");
        CHECK(std::fabs(played - default_target_lufs) <= 1.0);
    }
}

TEST_CASE("level auto through the limiter: a peaky programme, the umbrella in air before its compressible push, still plays at the target") {
    // The umbrella's default rain in air heard through its modes' taps alone (the model before the
    // compressible push, RendererConfig::air_push false) has a peak-to-loudness ratio of about 34 dB
    // (22 in vacuum, docs/canopy-air.md): raised to -23 LUFS its true peaks pass -1 dBTP by about 12 dB,
    // and the limiter's hold on them took 2.2 LU from the programme when the gain was target - measured.
    // The choice finds the gain through the limiter (level_choice.hpp). Tolerance 1 LU, as above. (With
    // the push, the server's default, the same rain needs 0.1 dB from the limiter: the push through
    // compressible air is softer above the modes than the incompressible one; docs/loudness.md.)
    if (ameoto::test::stop_here_if_sanitized("a scene in air builds in about 10 s under them; the limiter runs in the case above")) return;
    SceneDescription scene = *builtin_scene("umbrella");
    for (SurfaceDescription& s : scene.surfaces)
        if (s.kind == SurfaceKind::umbrella) s.air = true;
    RendererConfig base;
    base.seed = 1;
    base.limiter = true;
    RendererConfig config = configure_for_scene(base, scene);
    REQUIRE(config.air);
    config.air_push = false;   // the peakiest programme at hand
    const LevelChoice choice = choose_level(config, default_target_lufs);
    REQUIRE(std::isfinite(choice.measured_lufs));
    MESSAGE("umbrella in air, no push: measures " << choice.measured_lufs << " LUFS physical; level gain " << choice.gain_db << " dB, of which "
                                         << choice.limiter_db << " dB for the limiter; through it " << choice.played_lufs << " LUFS");
    // The limiter needed making up for (this is the case the plain difference missed), within the cap.
    CHECK(choice.limiter_db > 1.0);
    CHECK(choice.limiter_db <= max_limiter_share_db);
    CHECK(choice.gain_db == doctest::Approx(default_target_lufs - choice.measured_lufs + choice.limiter_db));
    CHECK(std::fabs(choice.played_lufs - default_target_lufs) <= 0.1);
    // Another target from the same recording (/loudness): quieter needs less of the limiter; louder, more,
    // up to the cap (12 dB), past which the programme plays under its target rather than be flattened.
    const auto t0 = std::chrono::steady_clock::now();
    const LevelChoice quieter = retarget_level(choice, -26.0);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE("retarget to -26 LUFS: level gain " << quieter.gain_db << " dB, " << quieter.limiter_db << " dB for the limiter, in " << took * 1e3 << " ms");
    CHECK(std::fabs(quieter.played_lufs + 26.0) <= 0.1);
    CHECK(quieter.limiter_db > 0.0);
    CHECK(quieter.limiter_db < choice.limiter_db);
    const LevelChoice louder = retarget_level(choice, -18.0);
    MESSAGE("retarget to -18 LUFS: level gain " << louder.gain_db << " dB, " << louder.limiter_db << " dB for the limiter, plays at " << louder.played_lufs << " LUFS");
    CHECK(louder.limiter_db == doctest::Approx(max_limiter_share_db));
    CHECK(louder.played_lufs < -18.0);
    CHECK(louder.played_lufs > choice.played_lufs + 3.0);
    CHECK(retarget_level(choice, default_target_lufs).gain_db == choice.gain_db);
    config.level_gain_db = choice.gain_db;
    const double played = render_lufs(config, 5.0);
    MESSAGE("played (5 s) " << played << " LUFS");
    CHECK(std::fabs(played - default_target_lufs) <= 1.0);
    // Without the limiter the choice is the plain difference: nothing to make up for.
    config.limiter = false;
    const LevelChoice plain = choose_level(config, default_target_lufs);
    CHECK(plain.limiter_db == 0.0);
    CHECK(plain.gain_db == doctest::Approx(default_target_lufs - plain.measured_lufs));
}

TEST_CASE("level auto is chosen from the scene's default rain, not the rain played: heavier rain stays louder") {
    // --rain 20 on the umbrella (default 2 mm/h): the same gain as at 2 mm/h, exactly, and the cloudburst
    // plays louder than the target by its physical amount: 20 LU or more at 50 mm/h (issue 21's headroom;
    // docs/levels.md measures the umbrella's slope at about 16 dB a decade of rate).
    RendererConfig config = scene_config("umbrella", 1);
    const LevelChoice at_default = choose_level(config, default_target_lufs, 1.0);
    RendererConfig heavy = config;
    heavy.rain_rate_mm_per_h = 50.0;   // what --rain 50 sets
    const LevelChoice at_heavy = choose_level(heavy, default_target_lufs, 1.0);
    CHECK(at_heavy.gain_db == at_default.gain_db);
    heavy.level_gain_db = at_default.gain_db;
    heavy.limiter = false;   // the unlimited level: the limiter would hold the peaks at -1 dBFS
    const double loud = render_lufs(heavy, 1.5);
    MESSAGE("umbrella at 50 mm/h with the 2 mm/h gain: " << loud << " LUFS");
    CHECK(loud - default_target_lufs >= 20.0);
}

TEST_CASE("level auto on a node measures the whole scene: every node gets the whole scene's gain") {
    // The street with the car and the window on node 2 (as renderer_nodes_test.cpp splits it). Were each
    // node measured alone, node 2 (two small surfaces) would be turned up more than node 1, and the
    // nodes' outputs would no longer sum to the whole scene's.
    SceneDescription scene = *builtin_scene("street");
    for (auto& s : scene.surfaces)
        if (s.name == "car" || s.name == "window") s.node = 2;
    RendererConfig base;
    base.seed = 1;
    RendererConfig whole = configure_for_scene(base, scene);
    const LevelChoice all = choose_level(whole, default_target_lufs, 0.5);
    REQUIRE(std::isfinite(all.measured_lufs));
    for (int node : {1, 2}) {
        RendererConfig part = whole;
        part.node = node;
        CHECK(choose_level(part, default_target_lufs, 0.5).gain_db == all.gain_db);
    }
}
