// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The command line of `ameoto bench`: parsed and checked, nothing run.
//
// Interface:
//   BenchOptions o;  std::string error;
//   BenchParse p = parse_bench_options(words, o, error);   // words: everything after "ameoto bench"
//   p == BenchParse::run | BenchParse::help | BenchParse::error (error says why)
//   parse_sizes("55,1000,10000")   // -> {55, 1000, 10000}; nullopt if malformed
//
// Grammar: ameoto bench SUITE [--json] [--seconds S] [--sizes N,N,...] [--runs R] [--no-faust]
// SUITE is "engine", "drop" or "scene". Options may come before or after the suite. Each suite takes
// only the options it reads (drop: --json, --runs; scene: --json, --seconds); another is an error.
// Limits: seconds 0.01..600 per measurement; sizes 1..200000 masses each, at most 16 of them;
// runs 1..101.

#include <optional>
#include <string>
#include <vector>

#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

struct BenchOptions {
    std::string suite;                    // "engine", "drop" or "scene"
    bool json = false;                    // one JSON object per measurement
    double seconds = 0.5;                 // time spent measuring each method at each size
    std::vector<int> sizes{55, 1000, 10000};   // target masses of the canopy panels
    int runs = 5;                         // timed runs per measurement (the median is reported)
    bool faust = true;                    // compare with Faust when it is installed
};

enum class BenchParse { run, help, error };

std::optional<std::vector<int>> parse_sizes(const std::string& text);
BenchParse parse_bench_options(const CommandWords& words, BenchOptions& options, std::string& error);

}  // namespace ameoto::client
