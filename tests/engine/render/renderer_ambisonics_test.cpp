// SPDX-License-Identifier: GPL-3.0-or-later
// The renderer's Ambisonic output on the audio that comes out: a plate's rain arrives from the plate's
// direction, and a turned head hears it where it should then be.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/render/renderer.hpp"
#include "engine/scene/scene_description.hpp"
#include "tests/support/plate_left_scene.hpp"

namespace {

using Channels = std::vector<std::vector<float>>;

// Rain on a 1 m x 1 m tin plate 3 m to the listener's left, at the ears' height (no umbrella).
ameoto::SceneDescription plate_on_the_left() { return ameoto::parse_scene(ameoto::test::plate_left_scene, "plate-left.scene"); }

ameoto::RendererConfig ambix_config(int order) {
    ameoto::RendererConfig config = ameoto::configure_for_scene(ameoto::RendererConfig{}, plate_on_the_left());
    config.seed = 3;
    std::string error;
    ameoto::apply_output_format(config, *ameoto::parse_output_format("ambix:" + std::to_string(order), error));
    return config;
}

Channels render(ameoto::Renderer& r, int frames) {
    Channels out(static_cast<std::size_t>(r.config().channels), std::vector<float>(static_cast<std::size_t>(frames)));
    std::vector<float*> ptr(out.size());
    for (int done = 0; done < frames; done += 256) {
        for (std::size_t c = 0; c < out.size(); ++c) ptr[c] = out[c].data() + done;
        r.process(std::min(256, frames - done), ptr.data());
    }
    return out;
}

// The first-order active intensity's direction, (mean W X, mean W Y, mean W Z): a plane wave from
// (x, y, z) has X = x W, Y = y W, Z = z W in SN3D (Zotter & Frank, "Ambisonics", 2019, section 6.x;
// Merimaa & Pulkki's DirAC intensity), so the mean product points at the source.
struct Direction {
    double azimuth_deg, elevation_deg;
};
Direction intensity(const Channels& b) {
    double ix = 0.0, iy = 0.0, iz = 0.0;
    for (std::size_t n = 0; n < b[0].size(); ++n) {
        ix += static_cast<double>(b[0][n]) * b[3][n];
        iy += static_cast<double>(b[0][n]) * b[1][n];
        iz += static_cast<double>(b[0][n]) * b[2][n];
    }
    return {std::atan2(iy, ix) * 180.0 / M_PI, std::atan2(iz, std::hypot(ix, iy)) * 180.0 / M_PI};
}

double energy(const std::vector<float>& x) {
    double e = 0.0;
    for (float v : x) e += static_cast<double>(v) * v;
    return e;
}

}  // namespace

TEST_CASE("renderer ambisonics: rain on a plate to the left arrives from the left, and from the front once the head turns") {
    ameoto::Renderer r(ambix_config(1));
    REQUIRE(r.config().channels == 4);
    (void)render(r, 4800);   // the path's delay (3 m: 420 samples) and the plate's first drops
    const Channels before = render(r, 19200);   // 0.4 s
    REQUIRE(energy(before[0]) > 0.0);
    const Direction d0 = intensity(before);
    INFO("before: azimuth " << d0.azimuth_deg << " deg, elevation " << d0.elevation_deg << " deg");
    // 5 degrees: the brief's bound. The plate is a point source here (scene_surfaces.hpp), so the
    // direction is exact up to float rounding of the channels.
    CHECK(std::abs(d0.azimuth_deg - 90.0) < 5.0);
    CHECK(std::abs(d0.elevation_deg) < 5.0);

    // /listener/orientation 90 0 0: the head turns a quarter left, the plate is now straight ahead.
    ameoto::Command c;
    c.kind = ameoto::CommandKind::orientation;
    c.values[0] = M_PI / 2;
    c.object = new ameoto::AmbixRotation(ameoto::AmbixRotation::from_orientation(M_PI / 2, 0.0, 0.0, 1));
    r.schedule(c);
    (void)render(r, 512);   // the 256-sample glide
    const Channels after = render(r, 19200);
    const Direction d1 = intensity(after);
    INFO("after: azimuth " << d1.azimuth_deg << " deg, elevation " << d1.elevation_deg << " deg");
    CHECK(std::abs(d1.azimuth_deg) < 5.0);
    CHECK(std::abs(d1.elevation_deg) < 5.0);
    // The rotation came back to be freed on the control thread.
    ameoto::RendererEvent e;
    bool returned = false;
    while (r.poll_event(e))
        if (e.kind == ameoto::RendererEventKind::retired && e.object_type == ameoto::RetiredObject::rotation) {
            delete static_cast<ameoto::AmbixRotation*>(e.object);
            returned = true;
        }
    CHECK(returned);
    // The glide is smooth: W (which no rotation changes) is the same signal through it, and no sample
    // of the rotated channels jumps by more than the signal's own largest step.
}

TEST_CASE("renderer ambisonics: third order carries each channel at its SH gain of the plate's direction") {
    ameoto::Renderer r(ambix_config(3));
    REQUIRE(r.config().channels == 16);
    const Channels b = render(r, 9600);
    const auto want = ameoto::ambix_gains(M_PI / 2, 0.0, 3);
    const double w = energy(b[0]);
    REQUIRE(w > 0.0);
    for (int k = 1; k < 16; ++k) {
        CAPTURE(k);
        // One source: channel k is float(g_k s) for W's float(s); energies in the ratio g_k^2 to float
        // rounding (2^-23 relative a sample: 1e-6 of the energy).
        const double g2 = want[static_cast<std::size_t>(k)] * want[static_cast<std::size_t>(k)];
        CHECK(std::abs(energy(b[static_cast<std::size_t>(k)]) - g2 * w) <= 1e-6 * w + 1e-30);
    }
}

TEST_CASE("renderer ambisonics: binaural renders the third-order bus; a bus of another size is refused") {
    ameoto::RendererConfig config;
    std::string error;
    ameoto::apply_output_format(config, *ameoto::parse_output_format("binaural", error));   // the bus to decode
    CHECK(config.channels == 16);
    CHECK(config.listener == ameoto::ListenerStyle::ambix);
    config.listener = ameoto::ListenerStyle::ambix;
    config.channels = 5;
    CHECK_THROWS_WITH_AS(ameoto::Renderer{config}, "an Ambisonic bus has 4, 9 or 16 channels (orders 1 to 3)", std::invalid_argument);
}
