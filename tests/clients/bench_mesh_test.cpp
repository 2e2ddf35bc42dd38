// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_mesh and bench_drive: the bodies `ameoto bench engine` measures, and
// the mi-faust triangle mesh rebuilt in ameoto with the .dsp's pluck.
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "clients/ameoto/bench_engine.hpp"
#include "clients/ameoto/bench_mesh.hpp"
#include "clients/ameoto/bench_methods.hpp"

#include "tests/clients/bench_test_bodies.hpp"

using namespace ameoto::client;

using ameoto::client::test::method_named;
using ameoto::client::test::render;

TEST_CASE("bench: the mi-faust triangle mesh as the .dsp builds it") {
    const BenchMesh mesh = mi_triangle_mesh();
    CHECK(mesh.nodes.size() == 52);   // 55 points, 3 of them the fixed corners
    CHECK(mesh.links.size() == 129);
    CHECK(mesh.anchors.size() == 6);  // 135 springDampers in all
    CHECK(mesh.time_step == 1.0);
    CHECK(mesh.alpha == ameoto::test::relative(5e-5));
    CHECK(mesh.beta == ameoto::test::relative(0.01));
    // The .dsp's routing: the pluck acts on m37 (t_m4_3), the output reads m41 (t_m5_1).
    CHECK(MiTriangle::faust_index(MiTriangle::pluck_i, MiTriangle::pluck_j) == 37);
    CHECK(MiTriangle::faust_index(MiTriangle::listen_i, MiTriangle::listen_j) == 41);
    CHECK(MiTriangle::faust_index(0, 9) == 54);   // the last ground
    CHECK(mesh.nodes[static_cast<std::size_t>(mesh.excite_node)].i == 3);
    CHECK(mesh.nodes[static_cast<std::size_t>(mesh.excite_node)].j == 4);
    // Every mass has its six lattice neighbours linked or anchored, or lies on a free edge.
    std::vector<int> springs(mesh.nodes.size(), 0);
    for (const auto& l : mesh.links) springs[static_cast<std::size_t>(l.a)]++, springs[static_cast<std::size_t>(l.b)]++;
    for (const auto& a : mesh.anchors) springs[static_cast<std::size_t>(a.a)]++;
    CHECK(springs[static_cast<std::size_t>(mesh.excite_node)] == 6);
}


TEST_CASE("bench: the pluck rings the mesh, the same on the network and on the grid") {
    const auto network = render(method_named("network explicit Verlet"), 2000);
    const auto grid = render(method_named("grid explicit Verlet (double)"), 2000);
    double peak = 0.0;
    for (double v : network) peak = std::max(peak, std::fabs(v));
    CHECK(peak > 1e-3);
    CHECK(max_relative_difference(grid, network) < 1e-12);
    CHECK(max_relative_difference(render(method_named("grid explicit Verlet (float)"), 2000), network) < 1e-3);
}


TEST_CASE("bench: canopy panels of the sizes asked for, as build_membrane makes them") {
    const BenchMesh panel = canopy_panel_mesh(300);
    CHECK(std::abs(static_cast<int>(panel.nodes.size()) - 300) <= 15);
    CHECK(panel.time_step == ameoto::test::relative(1.0 / 48000.0));
    CHECK(panel.alpha == 20.0);
    CHECK(panel.beta == 2e-6);
    CHECK(!panel.anchors.empty());
    for (const auto& l : panel.links) CHECK(l.k == doctest::Approx(1000.0 / std::sqrt(3.0)));
}
