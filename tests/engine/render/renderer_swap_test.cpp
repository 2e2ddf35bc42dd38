// Live material changes in the renderer: a canopy built elsewhere takes over by pointer, the old one
// rings out for 0.5 s (no click) and is handed back, never freed on the audio thread.

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "engine/render/renderer.hpp"
#include "tests/support/rt_probe_scope.hpp"

using namespace ameoto;

namespace {

struct Rig {
    RendererConfig config;
    std::unique_ptr<Renderer> renderer;
    std::vector<float> left, right;
    float* outs[2];
    explicit Rig(int block) : left(static_cast<std::size_t>(block)), right(static_cast<std::size_t>(block)) {
        config.rain_rate_mm_per_h = 0.0;
        renderer = std::make_unique<Renderer>(config);
        outs[0] = left.data();
        outs[1] = right.data();
    }
    void drop() {
        Command c;
        c.kind = CommandKind::drop;
        c.values[0] = 0.004;
        c.values[2] = 0.25;
        renderer->schedule(c);
    }
};

}  // namespace

TEST_CASE("a swapped canopy takes over without a click, and the old one comes back after ringing out") {
    Rig rig(480);
    rig.drop();
    rig.renderer->process(480, rig.outs);   // the old canopy rings
    const float before = rig.left.back();

    auto* vinyl = new Canopy(rig.config.canopy, MembraneMaterial::vinyl(), 1.0 / rig.config.sample_rate);
    Command swap;
    swap.kind = CommandKind::swap_canopy;
    swap.object = vinyl;
    swap.reply_to = 3;
    rig.renderer->schedule(swap);

    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        rig.renderer->process(480, rig.outs);
    }
    CHECK(audit.violations() == 0);
    // Continuity: the first sample after the swap continues the old canopy's ringing (it is still summed
    // in), so the step between blocks is no larger than the ringing's own sample-to-sample change.
    const float after = rig.left.front();
    CHECK(std::fabs(after - before) < 0.05f * std::max(1e-6f, std::fabs(before)) + 1e-4f);

    RendererEvent e;
    REQUIRE(rig.renderer->poll_event(e));
    CHECK(e.kind == RendererEventKind::swapped);
    CHECK(e.reply_to == 3);
    CHECK(&rig.renderer->canopy() == vinyl);

    // 0.5 s later the old canopy is handed back in a retired event (to be freed by the caller).
    void* retired = nullptr;
    for (int block = 0; block < 60 && !retired; ++block) {
        rig.renderer->process(480, rig.outs);
        while (rig.renderer->poll_event(e))
            if (e.kind == RendererEventKind::retired) retired = e.object;
    }
    REQUIRE(retired != nullptr);
    CHECK(retired != vinyl);
    delete static_cast<Canopy*>(retired);
}

TEST_CASE("a canopy of another geometry is handed straight back, unused") {
    Rig rig(64);
    CanopyGeometry other;
    other.panels = 6;
    auto* wrong = new Canopy(other, MembraneMaterial::nylon_canopy(), 1.0 / rig.config.sample_rate);
    Command swap;
    swap.kind = CommandKind::swap_canopy;
    swap.object = wrong;
    rig.renderer->schedule(swap);
    rig.renderer->process(64, rig.outs);
    RendererEvent e;
    REQUIRE(rig.renderer->poll_event(e));
    CHECK(e.kind == RendererEventKind::retired);
    CHECK(e.object == wrong);
    CHECK(&rig.renderer->canopy() != wrong);
    delete wrong;
}

TEST_CASE("liquid density scales a drop's impulse") {
    auto peak_for = [](double density) {
        Rig rig(4800);
        Command liquid;
        liquid.kind = CommandKind::set_liquid_density;
        liquid.values[0] = density;
        rig.renderer->schedule(liquid);
        rig.drop();
        rig.renderer->process(4800, rig.outs);
        float peak = 0;
        for (float s : rig.left) peak = std::max(peak, std::fabs(s));
        return peak;
    };
    // The membrane is linear and the pulse shape depends on D and V only, so the output scales exactly
    // with the drop's mass: 1400 / 998.
    CHECK(peak_for(1400.0) / peak_for(998.0) == doctest::Approx(1400.0 / 998.0).epsilon(1e-6));
}

TEST_CASE("a drop pushes the membrane down, against its upward normal") {
    Rig rig(96);
    rig.drop();   // 4 mm at terminal speed, at (0.25, 0)
    rig.renderer->process(24, rig.outs);   // 0.5 ms: during the impact (about D / V = 0.45 ms)
    const CanopyHit hit = rig.renderer->canopy().locate(0.25, 0.0);
    REQUIRE(hit.panel >= 0);
    CHECK(rig.renderer->canopy().displacement(hit.panel, hit.node) < 0.0);
}
