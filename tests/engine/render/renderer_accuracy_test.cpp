// SPDX-License-Identifier: GPL-3.0-or-later
// The accuracy knob applied where it has effect: a scene's budget sets the canopy panels' method when
// the renderer builds the scene (configure_for_scene -> RendererConfig::canopy_network -> Canopy), and
// the scene still sounds: a /drop on a canopy run by the chosen method is heard, finite.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "engine/render/renderer.hpp"

using namespace ameoto;

namespace {

// Renders 0.2 s with one 3 mm drop at the start; returns the peak |sample|.
double drop_peak(Renderer& r) {
    Command c{};
    c.kind = CommandKind::drop;
    c.values[0] = 3e-3;
    c.values[1] = 0.0;
    c.values[2] = 0.2;
    c.values[3] = 0.05;
    r.schedule(c);
    std::vector<float> left(256), right(256);
    float* outputs[] = {left.data(), right.data()};
    double peak = 0.0;
    for (int block = 0; block < 40; ++block) {
        r.process(256, outputs);
        for (int n = 0; n < 256; ++n) {
            REQUIRE(std::isfinite(left[n]));
            peak = std::max(peak, static_cast<double>(std::abs(left[n])));
        }
    }
    return peak;
}

}  // namespace

TEST_CASE("renderer accuracy: no budget keeps the default method; a budget builds the chosen one") {
    SceneDescription scene = *builtin_scene("umbrella");
    scene.rain.rate_mm_per_h = 0.0;
    RendererConfig base;
    RendererConfig plain = configure_for_scene(base, scene);
    CHECK(plain.canopy_network.integrator == Integrator::explicit_verlet);
    CHECK(plain.canopy_network.stability.min_sub_steps == 1);

    // The cents budget's choice reaches the config (building a renderer takes seconds: one is built below).
    scene.accuracy = AccuracyBudget{AccuracyMeasure::cents, 1.0};
    CHECK(configure_for_scene(base, scene).canopy_network.integrator == choose_method(*scene.accuracy).method.setting.integrator);

    scene.accuracy = AccuracyBudget{AccuracyMeasure::decibels, 2.0};
    const MethodChoice choice = choose_method(*scene.accuracy);
    CAPTURE(choice.reason);
    RendererConfig config = configure_for_scene(base, scene);
    CHECK(config.canopy_network.integrator == choice.method.setting.integrator);
    Renderer r(config);
    const TransverseNetwork& panel = r.canopy().panel(0).network;
    CHECK(panel.integrator() == choice.method.setting.integrator);
    if (choice.method.setting.integrator == Integrator::modal && choice.method.setting.modes > 0)
        CHECK(panel.modal().mode_count() == choice.method.setting.modes);
    if (conditionally_stable(choice.method.setting.integrator)) CHECK(panel.stability().sub_steps >= choice.method.setting.sub_steps);
    CHECK(drop_peak(r) > 1e-4);   // heard: the drop's impact radiates through the chosen method
}
