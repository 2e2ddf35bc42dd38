// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto bench lattices`: its rows are stretch_mode()'s values for every shape, the table it writes
// gives them back exactly, and its usage and refusals.
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "clients/ameoto/bench_command.hpp"
#include "clients/ameoto/bench_lattices.hpp"
#include "engine/core/lattice_ball.hpp"
#include "engine/models/drop.hpp"

using namespace ameoto;
using namespace ameoto::client;

TEST_CASE("bench lattices: one row per distinct shape, the committed table's values, written exactly") {
    const auto rows = compute_stretch_modes(27);   // up to 3 mm
    REQUIRE(rows.size() >= 5);
    const std::string source = stretch_mode_table_source(rows, 3.0);
    CHECK(source.find("ameoto bench lattices --max-diameter 3 --table engine/models/stretch_mode_table.cpp") != std::string::npos);
    for (const LatticeRow& r : rows) {
        CAPTURE(r.mode.masses);
        // The committed table holds every shape up to 8 mm: the same values.
        LatticeBallShape shape = lattice_ball_shape(r.mode.masses);
        REQUIRE(shape.last_shell_key == r.mode.last_shell_key);
        const auto tabulated = tabulated_stretch_mode(shape);
        REQUIRE(tabulated.has_value());
        CHECK(tabulated->lambda == r.mode.lambda);
        CHECK(tabulated->weight == r.mode.weight);
        // The written literal reads back to the same double (%a is exact).
        char literal[64];
        std::snprintf(literal, sizeof literal, "%a", r.mode.lambda);
        const auto at = source.find(", " + std::to_string(r.mode.links) + ", " + literal + ", ");
        CHECK(at != std::string::npos);
        CHECK(std::strtod(literal, nullptr) == r.mode.lambda);
    }
}

TEST_CASE("bench lattices: the command's usage, refusals and --table") {
    std::ostringstream out, err;
    const CommandIo io{{}, out, err};
    CHECK(run_bench({"lattices", "--help"}, io) == 0);
    CHECK(out.str().find("usage: ameoto bench lattices") != std::string::npos);
    CHECK(run_bench({"lattices", "--max-diameter", "30"}, io) == 2);
    CHECK(run_bench({"lattices", "--frobnicate"}, io) == 2);
    CHECK(run_bench({"lattices", "--table", ""}, io) == 2);
    const std::string path = std::string(AMEOTO_BIN_DIR) + "/../bench_lattices_test_table.cpp";
    out.str("");
    CHECK(run_bench({"lattices", "--max-diameter", "2", "--table", path}, io) == 0);
    CHECK(out.str().find("total") != std::string::npos);
    std::ifstream in(path);
    std::stringstream written;
    written << in.rdbuf();
    CHECK(written.str().find("tabulated_stretch_modes()") != std::string::npos);
    CHECK(written.str().find("--max-diameter 2 --table") != std::string::npos);
    std::remove(path.c_str());
    CHECK(run_bench({"lattices", "--table", "/nonexistent-dir/x.cpp", "--max-diameter", "1"}, io) == 1);
}
