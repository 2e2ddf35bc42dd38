// SPDX-License-Identifier: GPL-3.0-or-later
// A scene over several nodes (RendererConfig::node, the scene file's node=K): each node renders only its
// surfaces under the same listener, rain and seed, and the nodes' outputs sum to the whole scene's.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "engine/render/renderer.hpp"

namespace {

using NodeChannels = std::vector<std::vector<float>>;

// The street (umbrella, car, window, puddle) with the car and the window on node 2.
ameoto::SceneDescription split_street() {
    ameoto::SceneDescription scene = *ameoto::builtin_scene("street");
    for (auto& s : scene.surfaces)
        if (s.name == "car" || s.name == "window") s.node = 2;
    return scene;
}

// `frames` samples of node `node` (0: the whole scene) in blocks of 256, as ameotod renders them.
NodeChannels render_node(const ameoto::SceneDescription& scene, int node, int frames) {
    ameoto::RendererConfig config = ameoto::configure_for_scene(ameoto::RendererConfig{}, scene);
    config.seed = 7;
    config.node = node;
    ameoto::Renderer r(config);
    NodeChannels out(static_cast<std::size_t>(config.channels), std::vector<float>(static_cast<std::size_t>(frames)));
    std::vector<float*> ptr(out.size());
    for (int done = 0; done < frames; done += 256) {
        for (std::size_t c = 0; c < out.size(); ++c) ptr[c] = out[c].data() + done;
        r.process(std::min(256, frames - done), ptr.data());
    }
    return out;
}

float node_peak(const NodeChannels& x) {
    float p = 0.0f;
    for (const auto& ch : x)
        for (float v : ch) p = std::max(p, std::abs(v));
    return p;
}

}  // namespace

TEST_CASE("renderer nodes: the street split over two nodes sums to the whole street, sample for sample") {
    const ameoto::SceneDescription scene = split_street();
    constexpr int frames = 9600;   // 0.2 s at 48 kHz: at the street's 10 mm/h every surface is struck many times
    const NodeChannels whole = render_node(scene, 0, frames);
    const NodeChannels one = render_node(scene, 1, frames);
    const NodeChannels two = render_node(scene, 2, frames);
    const NodeChannels three = render_node(scene, 3, frames);   // a node the scene gives nothing

    // Each node plays its part: both sound, neither is the whole, node 3 is silent.
    CHECK(node_peak(one) > 0.0f);
    CHECK(node_peak(two) > 0.0f);
    CHECK(node_peak(three) == 0.0f);
    CHECK(one != whole);
    CHECK(two != whole);

    // The sum, sample for sample. The whole scene adds its surfaces into one frame in scene order
    // (umbrella, car, window, puddle, then the umbrella's texture grains); the nodes add theirs in another
    // grouping, so the two differ by float rounding only: at most one half-ulp per addition, five
    // additions, each partial sum no larger than the scene's peak (Higham, "Accuracy and Stability of
    // Numerical Algorithms", 2nd ed., eq. 4.4: |error| <= (n-1) u sum|x_i|), bounded here by
    // 8 * FLT_EPSILON * peak. A surface rendered with another surface's rain would differ by the
    // signal itself, orders of magnitude more.
    const float bound = 8.0f * std::numeric_limits<float>::epsilon() * node_peak(whole);
    float worst = 0.0f;
    for (std::size_t c = 0; c < whole.size(); ++c)
        for (std::size_t n = 0; n < whole[c].size(); ++n) worst = std::max(worst, std::abs(one[c][n] + two[c][n] - whole[c][n]));
    INFO("largest difference " << worst << " against the bound " << bound << " (peak " << node_peak(whole) << ")");
    CHECK(worst <= bound);
}

TEST_CASE("renderer nodes: a node number outside 0..16 is refused") {
    ameoto::RendererConfig config;
    config.node = 17;
    CHECK_THROWS_AS(ameoto::Renderer{config}, std::invalid_argument);
    config.node = -1;
    CHECK_THROWS_AS(ameoto::Renderer{config}, std::invalid_argument);
}

TEST_CASE("renderer nodes: the umbrella is rendered by its node only") {
    ameoto::SceneDescription scene = split_street();
    CHECK(ameoto::umbrella_on_node(scene, 0));
    CHECK(ameoto::umbrella_on_node(scene, 1));
    CHECK_FALSE(ameoto::umbrella_on_node(scene, 2));
    scene.surfaces[0].node = 2;   // the umbrella
    CHECK_FALSE(ameoto::umbrella_on_node(scene, 1));
    CHECK(ameoto::umbrella_on_node(scene, 2));
}
