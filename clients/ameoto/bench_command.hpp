// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto bench engine [--json] [--seconds S] [--sizes N,N,...] [--runs R] [--no-faust]`: measures
// the engine's methods (bench_engine.hpp); needs no server. docs/bench.md.
//
// Interface:
//   int status = run_bench(words, io);   // words: everything after "ameoto bench"
//   std::cout << bench_usage();          // ameoto bench --help, ameoto help bench
//
// Exit: 0 measured; 2 usage error.

#include <string>

#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

int run_bench(const CommandWords& words, const CommandIo& io);
std::string bench_usage();

}  // namespace ameoto::client
