// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_faust: the Faust peer of `ameoto bench engine`, and, where faust is
// installed, proof that ameoto's explicit scheme computes the same samples as Faust's own code.
// CI does not install faust: those checks then skip with a message (scripts/install-bench-deps).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "clients/ameoto/bench_engine.hpp"
#include "clients/ameoto/bench_faust.hpp"
#include "clients/ameoto/bench_mesh.hpp"
#include "clients/ameoto/bench_methods.hpp"

#include "tests/clients/bench_test_bodies.hpp"

using namespace ameoto::client;

using ameoto::client::test::method_named;
using ameoto::client::test::render;

TEST_CASE("bench: the driver Faust wraps around its class") {
    const std::string arch = faust_architecture();
    CHECK(arch.find("<<includeIntrinsic>>") != std::string::npos);
    CHECK(arch.find("<<includeclass>>") != std::string::npos);
    CHECK(arch.find("#define FAUSTFLOAT double") < arch.find("<<includeclass>>"));
    CHECK(arch.find("period = " + std::to_string(pluck_period) + ";") != std::string::npos);
    CHECK(arch.find("CLOCK_THREAD_CPUTIME_ID") != std::string::npos);
    CHECK(find_on_path("sh").has_value());
    CHECK_FALSE(find_on_path("ameoto-no-such-program").has_value());
}

TEST_CASE("bench: without faust on PATH the comparison says so plainly") {
    const char* saved = std::getenv("PATH");
    const std::string path = saved ? saved : "";
    setenv("PATH", "/ameoto-nowhere", 1);
    const FaustPeer peer = FaustPeer::prepare();
    setenv("PATH", path.c_str(), 1);
    CHECK_FALSE(peer.ready());
    CHECK(peer.problem() == "faust not installed: install it with scripts/install-bench-deps to compare");
}

TEST_CASE("bench: ameoto's explicit scheme computes Faust's samples (only where faust is installed)") {
    if (!find_on_path("faust") || !find_triangle_mesh_dsp()) {
        MESSAGE("skipped: faust or faust-common's triangleMesh.dsp not installed (scripts/install-bench-deps)");
        return;
    }
    const FaustPeer peer = FaustPeer::prepare();
    REQUIRE_MESSAGE(peer.ready(), peer.problem());
    std::string error;
    const auto faust = peer.dump(check_samples, error);
    REQUIRE_MESSAGE(faust.has_value(), error);
    double peak = 0.0;
    for (double v : *faust) peak = std::max(peak, std::fabs(v));
    CHECK(peak > 1e-3);   // the pluck really rang the mesh
    // Same model, same scheme: rounding only (different order of additions), after 4800 samples.
    CHECK(max_relative_difference(render(method_named("network explicit Verlet"), check_samples), *faust) < 1e-9);
    CHECK(max_relative_difference(render(method_named("grid explicit Verlet (double)"), check_samples), *faust) < 1e-9);
    CHECK(max_relative_difference(render(method_named("grid explicit Verlet (float)"), check_samples), *faust) < 1e-3);
    const auto timing = peer.time(0.05, 3, error);
    REQUIRE_MESSAGE(timing.has_value(), error);
    CHECK(timing->runs == 3);
    CHECK(timing->median_ns > 0.0);
}

