// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_options: `ameoto bench` command lines, parsed and checked.
#include "clients/ameoto/bench_options.hpp"

#include <doctest/doctest.h>

using namespace ameoto::client;

namespace {

struct Parsed {
    BenchParse result;
    BenchOptions options;
    std::string error;
};

Parsed parse(const CommandWords& words) {
    Parsed p;
    p.result = parse_bench_options(words, p.options, p.error);
    return p;
}

}  // namespace

TEST_CASE("bench options: the defaults") {
    const Parsed p = parse({"engine"});
    REQUIRE(p.result == BenchParse::run);
    CHECK(p.options.suite == "engine");
    CHECK_FALSE(p.options.json);
    CHECK(p.options.seconds == 0.5);
    CHECK(p.options.sizes == std::vector<int>{55, 1000, 10000});
    CHECK(p.options.runs == 5);
    CHECK(p.options.faust);
}

TEST_CASE("bench options: every option, before or after the suite, with or without =") {
    const Parsed p = parse({"--json", "engine", "--seconds", "2.5", "--sizes=100,2000", "--runs", "7", "--no-faust"});
    REQUIRE(p.result == BenchParse::run);
    CHECK(p.options.json);
    CHECK(p.options.seconds == 2.5);
    CHECK(p.options.sizes == std::vector<int>{100, 2000});
    CHECK(p.options.runs == 7);
    CHECK_FALSE(p.options.faust);
    CHECK(parse({"engine", "--seconds=0.01"}).options.seconds == 0.01);
    CHECK(parse({"engine", "--help"}).result == BenchParse::help);
    CHECK(parse({"-h"}).result == BenchParse::help);
}

TEST_CASE("bench options: sizes") {
    CHECK(parse_sizes("55") == std::vector<int>{55});
    CHECK(parse_sizes("55,1000,10000") == std::vector<int>{55, 1000, 10000});
    CHECK(parse_sizes("200000") == std::vector<int>{200000});
    for (const char* bad : {"", ",", "55,", ",55", "0", "-5", "+5", "5.5", "1e3", "200001", "55;1000", " 55", "abc",
                            "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17"})
        CHECK_MESSAGE(!parse_sizes(bad), bad);
}

TEST_CASE("bench options: errors say what is wrong") {
    auto error_of = [](const CommandWords& words) {
        const Parsed p = parse(words);
        CHECK(p.result == BenchParse::error);
        return p.error;
    };
    CHECK(error_of({}) == "which suite? (ameoto bench engine | drop | scene | formats)");
    CHECK(error_of({"--json"}) == "which suite? (ameoto bench engine | drop | scene | formats)");
    CHECK(error_of({"server"}) == "unknown suite 'server' (the suites: engine, drop, scene, formats)");
    CHECK(error_of({"engine", "extra"}) == "unexpected argument 'extra'");
    CHECK(error_of({"engine", "--fast"}) == "unknown option '--fast'");
    CHECK(error_of({"engine", "--json=1"}) == "--json takes no value");
    CHECK(error_of({"engine", "--seconds"}) == "--seconds needs a value");
    CHECK(error_of({"engine", "--seconds", "0"}) == "--seconds '0': give the seconds per measurement, 0.01..600");
    CHECK(error_of({"engine", "--seconds", "inf"}).starts_with("--seconds 'inf'"));
    CHECK(error_of({"engine", "--seconds", "601"}).starts_with("--seconds '601'"));
    CHECK(error_of({"engine", "--sizes", "10,x"}).starts_with("--sizes '10,x': give up to 16 mass counts"));
    CHECK(error_of({"engine", "--runs", "0"}) == "--runs '0': give the number of timed runs, 1..101");
    CHECK(error_of({"engine", "--runs", "102"}).starts_with("--runs '102'"));
    CHECK(error_of({"engine", "--runs", "2.5"}).starts_with("--runs '2.5'"));
}

TEST_CASE("bench options: the drop suite, and a suite that does not exist") {
    const Parsed drop = parse({"drop", "--json", "--runs", "3"});
    REQUIRE(drop.result == BenchParse::run);
    CHECK(drop.options.suite == "drop");
    CHECK(drop.options.json);
    CHECK(drop.options.runs == 3);
    const Parsed scene = parse({"scene", "--json", "--seconds", "0.5"});
    REQUIRE(scene.result == BenchParse::run);
    CHECK(scene.options.suite == "scene");
    // An option the suite would ignore is refused, wherever it stands: no figure is read as measured with it.
    CHECK(parse({"drop", "--seconds", "1"}).error == "--seconds does not apply to bench drop (it takes --json --runs)");
    CHECK(parse({"--sizes", "55", "drop"}).error == "--sizes does not apply to bench drop (it takes --json --runs)");
    CHECK(parse({"drop", "--no-faust"}).result == BenchParse::error);
    CHECK(parse({"scene", "--runs", "3"}).error == "--runs does not apply to bench scene (it takes --json --seconds)");
    CHECK(parse({"scene", "--sizes=55"}).result == BenchParse::error);
    const Parsed bad = parse({"rain"});
    CHECK(bad.result == BenchParse::error);
    CHECK(bad.error.find("engine, drop, scene") != std::string::npos);
}
