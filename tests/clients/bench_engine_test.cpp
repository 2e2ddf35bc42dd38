// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_engine: what `ameoto bench engine` prints (not how fast anything is).
#include "clients/ameoto/bench_engine.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <sched.h>

#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "clients/ameoto/bench_methods.hpp"

using namespace ameoto::client;

TEST_CASE("bench: the largest difference is relative to the reference's peak") {
    CHECK(max_relative_difference({1.0, 2.0, 3.0}, {1.0, 2.0, 4.0}) == ameoto::test::relative(0.25));
    CHECK(max_relative_difference({0.0, 0.0}, {0.0, 0.0}) == 0.0);
    CHECK(max_relative_difference({1.0}, {1.0, 2.0}) == INFINITY);   // missing samples never pass
    CHECK(max_relative_difference({NAN, 2.0}, {1.0, 2.0}) == INFINITY);
}

TEST_CASE("bench: `ameoto bench engine --json` prints one JSON object per measurement") {
    std::ostringstream out, err;
    const CommandIo io{[](const std::string&) { return std::optional<std::string>(); }, out, err};
    BenchOptions options;
    options.suite = "engine";
    options.json = true;
    options.seconds = 0.01;
    options.runs = 1;
    options.sizes = {20};
    options.faust = false;
    cpu_set_t before, after;
    REQUIRE(sched_getaffinity(0, sizeof before, &before) == 0);
    CHECK(run_engine_bench(options, io) == 0);
    REQUIRE(sched_getaffinity(0, sizeof after, &after) == 0);
    CHECK(CPU_EQUAL(&before, &after));   // the benchmark pins itself to one CPU, then lets go
    std::istringstream lines(out.str());
    std::string line;
    int count = 0, panel = 0, faust = 0;
    while (std::getline(lines, line)) {
        ++count;
        CHECK(line.starts_with("{\"suite\":\"engine\","));
        CHECK(line.ends_with("}"));
        if (line.find("\"mesh\":\"canopy panel\"") != std::string::npos) ++panel;
        if (line.find("\"body\":\"faust\"") != std::string::npos) {
            ++faust;
            CHECK(line.find("\"ns_per_sample\":null") != std::string::npos);
            CHECK(line.find("--no-faust") != std::string::npos);
        }
    }
    const int methods = static_cast<int>(bench_methods().size());
    CHECK(panel == methods);
    CHECK(faust == 1);
    CHECK(count == 2 * methods + 1);
}
