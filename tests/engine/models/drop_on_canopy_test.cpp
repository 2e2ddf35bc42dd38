// DropOnCanopy: a lattice drop on the canopy, end to end (engine/models/drop_on_canopy.hpp).
#include "engine/models/drop_on_canopy.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "tests/support/rt_probe_scope.hpp"

namespace {

using ameoto::DropOnCanopy;
using ameoto::DropOnCanopyConfig;
using ameoto::ListenerStyle;
using ameoto::SceneOutput;

DropOnCanopyConfig small_config() {
    DropOnCanopyConfig c;
    c.max_diameter = 5.2e-3;   // lattices up to 140 masses: quick to build
    return c;
}

struct Render {
    std::vector<std::vector<float>> channels;
    double peak = 0.0;
    bool finite = true;
};

Render render(DropOnCanopy& scene, int frames) {
    Render r;
    r.channels.assign(static_cast<std::size_t>(scene.channels()), std::vector<float>(static_cast<std::size_t>(frames)));
    std::vector<float*> out;
    for (auto& c : r.channels) out.push_back(c.data());
    constexpr int block = 256;
    for (int done = 0; done < frames; done += block) {
        std::vector<float*> at;
        for (float* p : out) at.push_back(p + done);
        scene.process(std::min(block, frames - done), at.data());
    }
    for (const auto& c : r.channels)
        for (float s : c) {
            if (!std::isfinite(s)) r.finite = false;
            r.peak = std::max(r.peak, static_cast<double>(std::fabs(s)));
        }
    return r;
}

}  // namespace

TEST_CASE("drop_on_canopy: a 5 mm water drop at terminal speed breaks up on nylon, masses conserved exactly") {
    DropOnCanopy scene(small_config());
    REQUIRE(scene.drop(5e-3, 0.0, 0.2, 0.0));
    const auto before = scene.stats();
    CHECK(before.active_drops == 1);
    CHECK(before.pieces == 1);
    CHECK(before.masses == 122);
    const Render r = render(scene, 4800);   // 0.1 s
    const auto s = scene.stats();
    MESSAGE("5 mm water on nylon after 0.1 s: ", s.pieces, " pieces, ", s.breakups, " breakups, ", s.link_breaks,
            " link breaks, ", s.collisions, " collisions, peak ", r.peak);
    CHECK(s.active_drops == 1);
    CHECK(s.pieces > 1);
    CHECK(s.breakups == s.pieces - 1);
    CHECK(s.collisions > 0);
    CHECK(s.masses == s.masses_at_spawn);
    CHECK(s.masses == 122);
    CHECK(s.mass_kg == s.mass_at_spawn_kg);   // exact: no mass created or removed
    CHECK(s.canopy_resets == 0);
    CHECK(r.finite);
    CHECK(r.peak > 0.0);
    CHECK(scene.snapshot().size() == 122u);
}

TEST_CASE("drop_on_canopy: a 0.5 mm drop is one mass and stays whole") {
    DropOnCanopy scene(small_config());
    REQUIRE(scene.drop(0.5e-3, 0.0, 0.2, 0.0));
    const Render r = render(scene, 2400);
    const auto s = scene.stats();
    CHECK(s.masses == 1);
    CHECK(s.pieces == 1);
    CHECK(s.breakups == 0);
    CHECK(s.collisions > 0);
    CHECK(s.mass_kg == s.mass_at_spawn_kg);
    CHECK(r.finite);
    CHECK(r.peak > 0.0);
}

TEST_CASE("drop_on_canopy: drop() refuses what it cannot place") {
    DropOnCanopy scene(small_config());
    CHECK_FALSE(scene.drop(6e-3, 0.0, 0.2, 0.0));    // above max_diameter
    CHECK_FALSE(scene.drop(0.0, 0.0, 0.2, 0.0));
    CHECK_FALSE(scene.drop(3e-3, -1.0, 0.2, 0.0));   // negative speed
    CHECK_FALSE(scene.drop(3e-3, 0.0, 2.0, 0.0));    // off the canopy
    CHECK(scene.drop(3e-3, 0.0, 0.2, 0.0));
    CHECK(scene.stats().spawned == 1);
}

TEST_CASE("drop_on_canopy: bad configurations are refused with a reason") {
    DropOnCanopyConfig c = small_config();
    c.channels = 0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c.channels = 17;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.guard_interval = -1;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.sample_rate = 100.0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.restitution = 1.5;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
    c = small_config();
    c.liquid.density = 1.0;
    CHECK_THROWS_AS(DropOnCanopy{c}, std::invalid_argument);
}

TEST_CASE("drop_on_canopy: panned outputs put a drop on its side, over 2 to 16 speakers") {
    for (int channels : {2, 4, 16}) {
        CAPTURE(channels);
        DropOnCanopyConfig c = small_config();
        c.channels = channels;
        c.listener = ListenerStyle::panned;
        DropOnCanopy scene(c);
        REQUIRE(scene.drop(3e-3, 0.0, 0.0, 0.25));   // panel at azimuth +90 deg: the left
        const Render r = render(scene, 1200);
        std::vector<double> energy;
        for (const auto& ch : r.channels) {
            double e = 0.0;
            for (float v : ch) e += static_cast<double>(v) * v;
            energy.push_back(e);
        }
        const auto loudest = std::max_element(energy.begin(), energy.end()) - energy.begin();
        // panning.hpp: stereo puts +90 deg hard left (channel 0); a ring from front-left clockwise has
        // +90 deg between the first speaker (front-left) and the last (back-left).
        if (channels == 2) CHECK(loudest == 0);
        if (channels == 4) CHECK((loudest == 0 || loudest == 3));
        CHECK(energy[static_cast<std::size_t>(loudest)] > 0.0);
    }
}

TEST_CASE("drop_on_canopy: a drop placed with no gap strikes at once, heard one acoustic delay later") {
    DropOnCanopyConfig c = small_config();
    c.gap_m = 0.0;
    DropOnCanopy scene(c);
    REQUIRE(scene.drop(4e-3, 0.0, 0.2, 0.05));
    float frame[1];
    scene.process_frame(frame);
    CHECK(scene.stats().collisions > 0);   // its lowest mass touches the cap in the first step
    CHECK(scene.acoustic_delay_samples(0.2, 0.05) > scene.latency_samples());
    CHECK(scene.latency_samples() == 42);   // 0.3 m under the shaft top, 343 m/s, 48 kHz: 0.29 m / 7.15 mm
}

TEST_CASE("drop_on_canopy: the same inputs render the same samples, bit for bit") {
    auto once = [] {
        DropOnCanopyConfig c = small_config();
        c.channels = 2;
        DropOnCanopy scene(c);
        scene.drop(3e-3, 0.0, 0.15, 0.05);
        scene.drop(2e-3, 5.0, -0.1, 0.2);
        return render(scene, 2400);
    };
    const Render a = once(), b = once();
    REQUIRE(a.channels.size() == 2u);
    CHECK(a.channels == b.channels);
    CHECK(a.peak > 0.0);
    CHECK(a.channels[0] != a.channels[1]);   // two ears hear different signals
}

TEST_CASE("drop_on_canopy: every material, liquid and output renders finite, non-silent audio") {
    for (const std::string& name : ameoto::membrane_material_names()) {
        DropOnCanopyConfig c = small_config();
        c.material = *ameoto::membrane_material(name);
        const bool seed = name == "seed-nylon";
        const int frames = seed ? 1200 : 2400;   // seed-nylon: 27 sub-steps per sample
        for (const SceneOutput output : {SceneOutput::far_field, SceneOutput::mass_pickup}) {
            c.output = output;
            const auto t0 = std::chrono::steady_clock::now();
            DropOnCanopy scene(c);
            REQUIRE(scene.drop(3e-3, 0.0, 0.2, 0.05));
            const Render r = render(scene, frames);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const std::string what = name + (output == SceneOutput::far_field ? " far field" : " pickup");
            INFO(what);
            CHECK(r.finite);
            CHECK(r.peak > 0.0);
            if (seed) MESSAGE("seed-nylon: ", frames, " samples in ", seconds, " s (27 sub-steps)");
        }
    }
    for (const ameoto::Liquid& liquid : ameoto::liquids::presets()) {
        DropOnCanopyConfig c = small_config();
        c.liquid = liquid;
        DropOnCanopy scene(c);
        REQUIRE(scene.drop(3e-3, 0.0, 0.2, 0.05));
        const Render r = render(scene, 2400);
        INFO(liquid.name);
        CHECK(r.finite);
        CHECK(r.peak > 0.0);
        CHECK(scene.stats().mass_kg == scene.stats().mass_at_spawn_kg);
    }
}

TEST_CASE("drop_on_canopy: drop() and process() never allocate") {
    DropOnCanopyConfig c = small_config();
    c.channels = 2;
    DropOnCanopy scene(c);
    std::vector<float> left(256), right(256);
    float* out[] = {left.data(), right.data()};
    scene.process(256, out);   // warm up
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        scene.drop(5e-3, 0.0, 0.2, 0.0);
        for (int b = 0; b < 20; ++b) scene.process(256, out);   // impact and breakup
        scene.drop(2e-3, 0.0, -0.2, 0.1);
        for (int b = 0; b < 4; ++b) scene.process(256, out);
        (void)scene.stats();
    }
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    CHECK(scene.stats().pieces > 2);
}
