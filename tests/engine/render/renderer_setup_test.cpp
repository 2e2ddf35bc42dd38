// SPDX-License-Identifier: GPL-3.0-or-later
// engine/render/renderer_setup.cpp: a scene's umbrella keys reach the scene that is built from it. The
// impact= key (issue 19, part 3) chooses how drops meet the canopy for the full model and for the impact
// templates recorded from it, so the cheaper tier plays the same exchange as the full one.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/render/renderer.hpp"
#include "engine/scene/scene_description.hpp"

using namespace ameoto;

namespace {

// The downward impulse (N s) of the recorded template nearest `diameter_m`: -sum of its forces times T.
double template_impulse(const ImpactTemplateTable& t, double diameter_m) {
    const int k = t.nearest(diameter_m);
    double sum = 0.0;
    for (int n = 0; n < t.used[static_cast<std::size_t>(k)]; ++n) sum += t.force(k, n);
    return -sum / t.sample_rate;
}

}  // namespace

TEST_CASE("renderer setup: the umbrella's impact= key reaches the drops and the templates recorded from them") {
    SceneDescription scene = builtin_scene("umbrella").value();
    RendererConfig wet_config = configure_for_scene(RendererConfig{}, scene);
    CHECK(wet_config.impact == ImpactModel::wet);   // the default: a liquid's impulse
    for (SurfaceDescription& s : scene.surfaces)
        if (s.kind == SurfaceKind::umbrella) s.impact = ImpactModel::seed;
    RendererConfig seed_config = configure_for_scene(RendererConfig{}, scene);
    CHECK(seed_config.impact == ImpactModel::seed);

    const auto wet = Renderer::make_scene(wet_config);
    const auto seed = Renderer::make_scene(seed_config);
    CHECK(wet->drops.config().impact == ImpactModel::wet);
    CHECK(seed->drops.config().impact == ImpactModel::seed);
    // The templates were recorded with each exchange. A wet drop gives the membrane its momentum m V
    // (Gordillo et al. 2018; acoustics.md section 3); the seed's elastic exchange returns it too, twice
    // that (issue 19). A 1 mm drop is one mass: 2 within 10 % (measured 1.98, 2026-12-02). Larger ones are
    // lattices that the seed's exchange tears, so that less comes back (1.84 at 2 mm, 1.62 at 3 mm): there,
    // more than the wet impulse by 40 % and less than twice it by 10 %.
    const double one = template_impulse(seed->templates, 1e-3) / template_impulse(wet->templates, 1e-3);
    MESSAGE("template impulse, seed over wet, at 1 mm: " << one);
    CHECK(one == doctest::Approx(2.0).epsilon(0.1));
    for (double d : {2e-3, 3e-3}) {
        const double ratio = template_impulse(seed->templates, d) / template_impulse(wet->templates, d);
        MESSAGE("template impulse, seed over wet, at " << d * 1e3 << " mm: " << ratio);
        CHECK(ratio > 1.4);
        CHECK(ratio < 2.2);
    }
}
