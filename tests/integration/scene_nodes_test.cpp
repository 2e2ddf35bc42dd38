// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod --node K: the real daemon plays only node K's part of a scene file (node=K on its surfaces),
// and the parts, rendered offline with the same seed, sum to the whole scene.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "tests/support/child_process.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;

namespace {

// The street with its car and window on node 2.
constexpr const char* street_split =
    "ameoto-scene 3\n"
    "name street-split\n"
    "rain rate=10\n"
    "surface umbrella kind=umbrella material=nylon size=1 z=1.9\n"
    "surface car kind=plate material=car-roof size=1.2x1 x=2.5 y=-1.5 z=1.4 node=2\n"
    "surface window kind=plate material=glass size=0.8x0.6 x=-2 y=2 z=1 node=2\n"
    "surface puddle kind=water material=puddle size=1x0.8 x=1 y=1 z=0\n";

ameoto::test::WavData render_part(const std::string& scene, const std::string& wav, const std::string& node) {
    std::vector<std::string> argv{ameoto::test::ameotod, "--backend", "null", "--offline", "--duration", "0.2", "--seed", "7",
                                  "--scene", scene, "--output", wav, "--port", "0",
                                  // Physical level: --level auto would choose each node's gain from its own part
                                  // (docs/loudness.md), and the parts would no longer sum to the whole.
                                  "--level", "physical"};
    if (!node.empty()) argv.insert(argv.end(), {"--node", node});
    ameoto::test::ChildProcess p(argv);
    REQUIRE_MESSAGE(p.wait(60s) == 0, p.output());
    return ameoto::test::read_wav(wav);
}

float wav_peak(const ameoto::test::WavData& w) {
    float p = 0.0f;
    for (float v : w.samples) p = std::max(p, std::abs(v));
    return p;
}

}  // namespace

TEST_CASE("ameotod --node K plays node K's surfaces; the nodes' WAVs sum to the whole scene's") {
    ameoto::test::TempDir dir("ameoto-scene-nodes");
    const std::string scene = (dir.path() / "street-split.scene").string();
    std::ofstream(scene) << street_split;
    const auto whole = render_part(scene, (dir.path() / "whole.wav").string(), "");
    const auto one = render_part(scene, (dir.path() / "one.wav").string(), "1");
    const auto two = render_part(scene, (dir.path() / "two.wav").string(), "2");
    REQUIRE(whole.ok);
    REQUIRE(one.ok);
    REQUIRE(two.ok);
    REQUIRE(one.samples.size() == whole.samples.size());
    REQUIRE(two.samples.size() == whole.samples.size());
    CHECK(wav_peak(one) > 0.0f);
    CHECK(wav_peak(two) > 0.0f);
    CHECK(one.samples != whole.samples);
    // Float rounding of adding the surfaces in another grouping only (the bound and its source:
    // tests/engine/render/renderer_nodes_test.cpp).
    const float bound = 8.0f * std::numeric_limits<float>::epsilon() * wav_peak(whole);
    float worst = 0.0f;
    for (std::size_t i = 0; i < whole.samples.size(); ++i) worst = std::max(worst, std::abs(one.samples[i] + two.samples[i] - whole.samples[i]));
    INFO("largest difference " << worst << " against " << bound);
    CHECK(worst <= bound);
}
