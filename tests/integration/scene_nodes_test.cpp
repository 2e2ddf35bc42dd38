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
#include "tests/support/street_split_scene.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;

namespace {

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

}  // namespace

TEST_CASE("ameotod --node K plays node K's surfaces; the nodes' WAVs sum to the whole scene's") {
    ameoto::test::TempDir dir("ameoto-scene-nodes");
    const std::string scene = (dir.path() / "street-split.scene").string();
    std::ofstream(scene) << ameoto::test::street_split_scene;
    const auto whole = render_part(scene, (dir.path() / "whole.wav").string(), "");
    const auto one = render_part(scene, (dir.path() / "one.wav").string(), "1");
    const auto two = render_part(scene, (dir.path() / "two.wav").string(), "2");
    REQUIRE(whole.ok);
    REQUIRE(one.ok);
    REQUIRE(two.ok);
    REQUIRE(one.samples.size() == whole.samples.size());
    REQUIRE(two.samples.size() == whole.samples.size());
    CHECK(one.peak() > 0.0f);
    CHECK(two.peak() > 0.0f);
    CHECK(one.samples != whole.samples);
    // Float rounding of adding the surfaces in another grouping only (the bound and its source:
    // tests/engine/render/renderer_nodes_test.cpp).
    const float bound = 8.0f * std::numeric_limits<float>::epsilon() * whole.peak();
    float worst = 0.0f;
    for (std::size_t i = 0; i < whole.samples.size(); ++i) worst = std::max(worst, std::abs(one.samples[i] + two.samples[i] - whole.samples[i]));
    INFO("largest difference " << worst << " against " << bound);
    CHECK(worst <= bound);
}
