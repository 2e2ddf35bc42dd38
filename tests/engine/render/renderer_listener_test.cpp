// SPDX-License-Identifier: GPL-3.0-or-later
// The listener's turns on the audio that comes out (renderer_listener.cpp, listener_rotation.hpp):
// /listener's facing rotates the Ambisonic world bus (the surfaces) and not the body bus (the held
// umbrella), the head's orientation rotates both, and on stereo the head re-pans every sound by its
// turned direction, gliding.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/render/listener_rotation.hpp"
#include "engine/render/renderer.hpp"
#include "engine/scene/scene_description.hpp"
#include "tests/support/plate_left_scene.hpp"
#include "tests/support/relative_approx.hpp"

namespace listener_test {

using Channels = std::vector<std::vector<float>>;

// Rain on a 1 m x 1 m tin plate 3 m to the listener's left, at the ears' height (no umbrella).
ameoto::SceneDescription plate_left() { return ameoto::parse_scene(ameoto::test::plate_left_scene, "plate-left.scene"); }

ameoto::RendererConfig config_for(const ameoto::SceneDescription& scene, const char* format, double rain_mm_per_h = -1.0) {
    ameoto::RendererConfig config = ameoto::configure_for_scene(ameoto::RendererConfig{}, scene);
    config.seed = 3;
    if (rain_mm_per_h >= 0.0) config.rain_rate_mm_per_h = rain_mm_per_h;
    std::string error;
    ameoto::apply_output_format(config, *ameoto::parse_output_format(format, error));
    return config;
}

Channels run(ameoto::Renderer& r, int frames) {
    Channels out(static_cast<std::size_t>(r.config().channels), std::vector<float>(static_cast<std::size_t>(frames)));
    std::vector<float*> ptr(out.size());
    for (int done = 0; done < frames; done += 256) {
        for (std::size_t c = 0; c < out.size(); ++c) ptr[c] = out[c].data() + done;
        r.process(std::min(256, frames - done), ptr.data());
    }
    return out;
}

ameoto::Command facing(double rad, const ameoto::SceneDescription& scene) {
    ameoto::Command c;
    c.kind = ameoto::CommandKind::listener;
    c.values[0] = scene.listener.x_m;
    c.values[1] = scene.listener.y_m;
    c.values[2] = scene.listener.z_m;
    c.values[3] = rad;
    return c;
}

// As the daemon builds it (packet_dispatch.cpp): the matrix for the stream's order (0 off Ambisonics).
ameoto::Command head(double yaw, double pitch, double roll, int order) {
    ameoto::Command c;
    c.kind = ameoto::CommandKind::orientation;
    c.values[0] = yaw;
    c.values[1] = pitch;
    c.values[2] = roll;
    c.object = new ameoto::AmbixRotation(ameoto::AmbixRotation::from_orientation(yaw, pitch, roll, order));
    return c;
}

// Frees the rotations handed back; counts scene changes (a rebuild would show as one).
int drain(ameoto::Renderer& r) {
    int scene_events = 0;
    for (ameoto::RendererEvent e; r.poll_event(e);) {
        if (e.kind == ameoto::RendererEventKind::retired && e.object_type == ameoto::RetiredObject::rotation)
            delete static_cast<ameoto::AmbixRotation*>(e.object);
        else if (e.kind == ameoto::RendererEventKind::retired || e.kind == ameoto::RendererEventKind::swapped)
            ++scene_events;
    }
    return scene_events;
}

// The first-order active intensity's azimuth, atan2(mean W Y, mean W X) (renderer_ambisonics_test.cpp:
// a plane wave from (x, y, z) has X = x W, Y = y W in SN3D, so the mean product points at the source).
double azimuth_deg(const Channels& b) {
    double ix = 0.0, iy = 0.0;
    for (std::size_t n = 0; n < b[0].size(); ++n) {
        ix += static_cast<double>(b[0][n]) * b[3][n];
        iy += static_cast<double>(b[0][n]) * b[1][n];
    }
    return std::atan2(iy, ix) * 180.0 / M_PI;
}

double angle_between_deg(double a, double b) { return std::abs(std::remainder(a - b, 360.0)); }

double energy_db(const std::vector<float>& x) {
    double e = 1e-300;
    for (float v : x) e += static_cast<double>(v) * v;
    return 10.0 * std::log10(e);
}

}  // namespace listener_test

using namespace listener_test;

TEST_CASE("facing turn: the world bus turned by f is the encoding of every direction at azimuth - f, orders 1 to 3") {
    ameoto::Random rng(11);
    for (int order = 1; order <= 3; ++order)
        for (int trial = 0; trial < 20; ++trial) {
            const double az = (rng.uniform() * 2.0 - 1.0) * M_PI, el = (rng.uniform() - 0.5) * M_PI,
                         f = (rng.uniform() * 2.0 - 1.0) * 2.0 * M_PI;
            const auto g = ameoto::ambix_gains(az, el, order), want = ameoto::ambix_gains(az - f, el, order);
            float in[16] = {}, out[16] = {};
            for (int k = 0; k < 16; ++k) in[k] = static_cast<float>(g[static_cast<std::size_t>(k)]);
            ameoto::FacingTurn t;
            t.reset(order, f);
            CHECK(t.active());
            t.step();
            t.add_turned(in, out);
            for (int k = 0; k < ameoto::ambix_channels(order); ++k) {
                CAPTURE(order);
                CAPTURE(k);
                CHECK(std::abs(out[k] - want[static_cast<std::size_t>(k)]) < 1e-6);   // float channels: 2^-23 of 1
            }
        }
    // The glide: halfway, the matrices' blend; at the end exactly the target, and back at rest at 0.
    ameoto::FacingTurn t;
    t.reset(1, 0.0);
    CHECK_FALSE(t.active());
    t.turn_to(M_PI / 2);
    for (int n = 0; n < ameoto::FacingTurn::glide_frames / 2; ++n) t.step();
    float x_in[4] = {1, 0, 0, 1}, mid[4] = {};   // W and X: a source straight ahead
    t.add_turned(x_in, mid);
    CHECK(mid[3] == ameoto::test::relative(0.5));   // X: half of cos 0 + half of cos 90
    CHECK(mid[1] == ameoto::test::relative(-0.5));  // Y: the source moves to the right as the body turns left
    for (int n = 0; n < ameoto::FacingTurn::glide_frames; ++n) t.step();
    t.turn_to(0.0);
    for (int n = 0; n < ameoto::FacingTurn::glide_frames; ++n) t.step();
    CHECK_FALSE(t.active());
}

TEST_CASE("ambisonics: /listener facing 90 rotates the world bus: the plate on the left comes from the front, nothing rebuilt") {
    const ameoto::SceneDescription scene = plate_left();
    ameoto::Renderer r(config_for(scene, "ambix:1"));
    (void)run(r, 4800);   // the 3 m path's delay and the plate's first drops
    const double before = azimuth_deg(run(r, 9600));
    MESSAGE("before: " << before << " deg");
    CHECK(angle_between_deg(before, 90.0) < 5.0);   // the brief's bound
    const ameoto::SceneSurfaces* surfaces = &r.surfaces();
    const double delay = r.surfaces().delay_samples(0);
    r.schedule(facing(M_PI / 2, scene));
    (void)run(r, 512);   // the 256-sample glide
    const double after = azimuth_deg(run(r, 9600));
    MESSAGE("after facing 90: " << after << " deg");
    CHECK(angle_between_deg(after, 0.0) < 5.0);
    CHECK(r.facing_turn().active());
    CHECK(&r.surfaces() == surfaces);                  // the same surfaces, not rebuilt
    CHECK(r.surfaces().delay_samples(0) == delay);     // the same path: a turn on the spot
    CHECK(drain(r) == 0);                              // no scene was swapped in or handed back

    // With the head turned a further 90 left (yaw), the plate is behind-right... exactly right: -90.
    r.schedule(head(M_PI / 2, 0.0, 0.0, 1));
    (void)run(r, 512);
    const double both = azimuth_deg(run(r, 9600));
    MESSAGE("facing 90 + yaw 90: " << both << " deg");
    CHECK(angle_between_deg(both, -90.0) < 5.0);
    CHECK(drain(r) == 0);
}

TEST_CASE("ambisonics: a facing and the same yaw as a head orientation give the same field (to float rounding)") {
    // Facing f then no head turn, against facing 0 and head yaw f: H_world = R(yaw) Z(0) = R(0) Z(f).
    const ameoto::SceneDescription scene = plate_left();
    ameoto::Renderer by_facing(config_for(scene, "ambix:3")), by_head(config_for(scene, "ambix:3"));
    by_facing.schedule(facing(0.7, scene));
    by_head.schedule(head(0.7, 0.0, 0.0, 3));
    const Channels a = run(by_facing, 4800), b = run(by_head, 4800);
    double worst = 0.0, peak = 0.0;
    for (std::size_t ch = 0; ch < a.size(); ++ch)
        for (std::size_t n = 0; n < a[ch].size(); ++n) {
            worst = std::max(worst, static_cast<double>(std::abs(a[ch][n] - b[ch][n])));
            peak = std::max(peak, static_cast<double>(std::abs(a[ch][n])));
        }
    REQUIRE(peak > 0.0);
    MESSAGE("worst difference " << worst / peak << " of the peak");
    // The two glides differ (a pairwise blend against a fitted matrix's crossfade: the same weights), and
    // the float sums' order: 1e-5 of the peak.
    CHECK(worst <= 1e-5 * peak);
    (void)drain(by_facing);
    (void)drain(by_head);
}

TEST_CASE("ambisonics: the held umbrella turns with the body: a facing leaves its drop's direction, a head yaw moves it") {
    // No rain: one lattice drop on the canopy's left half, heard from its panel's direction; the canopy in
    // vacuum, whatever the default (in air its modes radiate from every panel: docs/canopy-air.md).
    ameoto::SceneDescription scene = *ameoto::builtin_scene("umbrella");
    scene.surfaces[0].air = false;
    auto one_drop = [&](ameoto::Renderer& r) {
        ameoto::Command d;
        d.kind = ameoto::CommandKind::drop;
        d.values[0] = 0.004;
        d.values[1] = 0.0;
        d.values[2] = 0.05;
        d.values[3] = 0.2;
        d.timed = true;
        d.frame = 600;
        r.schedule(d);
        return azimuth_deg(run(r, 4800));
    };
    ameoto::Renderer plain(config_for(scene, "ambix:1", 0.0)), turned(config_for(scene, "ambix:1", 0.0)),
        headed(config_for(scene, "ambix:1", 0.0));
    turned.schedule(facing(M_PI / 2, scene));
    headed.schedule(head(M_PI / 2, 0.0, 0.0, 1));
    const double a = one_drop(plain), b = one_drop(turned), c = one_drop(headed);
    MESSAGE("drop heard at " << a << " deg; after facing 90: " << b << " deg; after head yaw 90: " << c << " deg");
    CHECK(a > 30.0);                               // the left half: its panel's azimuth, a positive one
    CHECK(angle_between_deg(a, b) < 1.0);          // the umbrella turned with the body
    CHECK(angle_between_deg(c, a - 90.0) < 5.0);   // the head turned under it
    (void)drain(plain);
    (void)drain(turned);
    (void)drain(headed);
}

TEST_CASE("stereo: the head's orientation re-pans every sound by its turned direction, gliding") {
    const ameoto::SceneDescription scene = plate_left();
    auto balance_db = [](const Channels& s) { return energy_db(s[0]) - energy_db(s[1]); };   // left over right
    ameoto::Renderer r(config_for(scene, "stereo"));
    (void)run(r, 4800);
    const double left = balance_db(run(r, 9600));
    MESSAGE("plate on the left: left - right " << left << " dB");
    CHECK(left > 20.0);   // pan_gains at +90: the left speaker alone (constant power: cos 0 against sin 0)
    r.schedule(head(M_PI / 2, 0.0, 0.0, 0));   // yaw 90: ahead
    (void)run(r, 512);
    const double ahead = balance_db(run(r, 9600));
    CHECK(std::abs(ahead) < 0.5);   // equal gains: the energies of one signal
    r.schedule(head(M_PI, 0.0, 0.0, 0));       // yaw 180: the plate on the right
    (void)run(r, 512);
    CHECK(balance_db(run(r, 9600)) < -20.0);
    CHECK(drain(r) == 0);

    // Roll 90 (the right ear lowered, the left ear up) on a plate 45 degrees to the front-left: heard
    // from H^T v = (0.71, 0, -0.71), ahead and below, so the middle. A pan by the azimuth alone (no
    // full rotation) would leave it at 45.
    ameoto::SceneDescription front_left = scene;
    front_left.surfaces[0].x_m = 3.0;
    ameoto::Renderer fl(config_for(front_left, "stereo"));
    (void)run(fl, 4800);
    const double at_45 = balance_db(run(fl, 4800));
    CHECK(at_45 > 3.0);
    fl.schedule(head(0.0, 0.0, M_PI / 2, 0));
    (void)run(fl, 512);
    const double rolled = balance_db(run(fl, 4800));
    MESSAGE("front-left: " << at_45 << " dB; rolled 90: " << rolled << " dB");
    CHECK(std::abs(rolled) < 0.5);
    CHECK(drain(fl) == 0);

    // The glide: against the same stream unturned, the left channel's ratio follows the gains' linear
    // glide from cos(0) to cos(45 deg) over 256 samples (one source: out = g(n) s[n]), no jump.
    ameoto::Renderer plain(config_for(scene, "stereo")), turning(config_for(scene, "stereo"));
    ameoto::Command turn = head(M_PI / 2, 0.0, 0.0, 0);
    turn.timed = true;
    turn.frame = 4800;
    turning.schedule(turn);
    const Channels p = run(plain, 5400), t = run(turning, 5400);
    const double g0 = 1.0, g1 = std::sqrt(0.5);   // pan_gains: left at +90 deg, then at 0 deg
    int checked = 0;
    for (int n = 4790; n < 5400; ++n) {
        const float pn = p[0][static_cast<std::size_t>(n)];
        if (std::abs(pn) < 1e-3f * 1e-3f) continue;   // too small a sample for a ratio
        const double k = std::clamp((n - 4800) / 256.0, 0.0, 1.0);
        const double want = g0 + (g1 - g0) * k;   // the gain at sample n, over the gain before
        CAPTURE(n);
        CHECK(t[0][static_cast<std::size_t>(n)] / pn == ameoto::test::relative(want).epsilon(0.01));
        ++checked;
    }
    CHECK(checked > 300);
    (void)drain(plain);
    (void)drain(turning);
}

TEST_CASE("stereo: the held umbrella's panels re-pan with the head; at rest again the samples are the unturned ones") {
    // In vacuum (the Rayleigh path's panel sums re-mixed), whatever the default; in air:
    // drop_on_canopy_turn_test.cpp.
    const ameoto::SceneDescription scene = [] {
        ameoto::SceneDescription s = *ameoto::builtin_scene("umbrella");
        s.surfaces[0].air = false;
        return s;
    }();
    auto with_drop = [](ameoto::Renderer& r) {
        ameoto::Command d;
        d.kind = ameoto::CommandKind::drop;
        d.values[0] = 0.004;
        d.values[2] = 0.05;
        d.values[3] = 0.2;   // on the left half
        d.timed = true;
        d.frame = 600;
        r.schedule(d);
        return run(r, 4800);
    };
    auto balance_db = [](const Channels& s) { return energy_db(s[0]) - energy_db(s[1]); };
    ameoto::Renderer plain(config_for(scene, "stereo", 0.0)), turned(config_for(scene, "stereo", 0.0)),
        back(config_for(scene, "stereo", 0.0));
    turned.schedule(head(M_PI, 0.0, 0.0, 0));   // the head turned round under the umbrella
    back.schedule(head(M_PI, 0.0, 0.0, 0));
    (void)run(plain, 512);
    (void)run(turned, 512);
    (void)run(back, 256);
    back.schedule(head(0.0, 0.0, 0.0, 0));
    (void)run(back, 256);   // the glide home, before the drop
    const Channels a = with_drop(plain), b = with_drop(turned), c = with_drop(back);
    MESSAGE("left - right " << balance_db(a) << " dB; head turned round: " << balance_db(b) << " dB");
    // The drop's panel is centred at +90 degrees: the left speaker alone; turned round, the right alone.
    CHECK(balance_db(a) > 20.0);
    CHECK(balance_db(b) < -20.0);
    CHECK(c == a);   // back at rest: the layout's own gains, bit for bit
    (void)drain(plain);
    (void)drain(turned);
    (void)drain(back);
}

TEST_CASE("ears: the head's orientation turns nothing (the protocol refuses it there); the rotation still goes back") {
    const ameoto::SceneDescription scene = plate_left();
    ameoto::Renderer plain(config_for(scene, "ears")), turned(config_for(scene, "ears"));
    turned.schedule(head(M_PI / 2, 0.2, 0.1, 0));
    const Channels a = run(plain, 2400), b = run(turned, 2400);
    REQUIRE(energy_db(a[0]) > -200.0);   // the plate is heard (its path is 420 samples)
    CHECK(a == b);
    bool returned = false;
    for (ameoto::RendererEvent e; turned.poll_event(e);)
        if (e.kind == ameoto::RendererEventKind::retired && e.object_type == ameoto::RetiredObject::rotation) {
            delete static_cast<ameoto::AmbixRotation*>(e.object);
            returned = true;
        }
    CHECK(returned);
}
