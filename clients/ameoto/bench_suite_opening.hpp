// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The opening that every `ameoto bench SUITE` with options of its own shares (accuracy, lattices):
// parse the words; a usage error is printed with a pointer to the suite's --help (exit 2) and --help
// prints the suite's usage (exit 0); otherwise the suite runs.
//
// Interface:
//   if (const auto done = open_bench_suite(words, io, "accuracy", options, parse, accuracy_bench_usage))
//       return *done;                      // the exit status: the suite does not run
//   // parse: bool(const CommandWords&, Options&, std::string& error, bool& help), false on an error
//   // usage: std::string()

#include <optional>
#include <string>
#include <string_view>

#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/exit_status.hpp"

namespace ameoto::client {

template <typename Options, typename Parse, typename Usage>
std::optional<int> open_bench_suite(const CommandWords& words, const CommandIo& io, std::string_view suite, Options& options,
                                    Parse&& parse, Usage&& usage) {
    std::string error;
    bool help = false;
    if (!parse(words, options, error, help)) {
        io.err << "ameoto bench: " << error << "\n(see ameoto bench " << suite << " --help)\n";
        return exit_status::usage;
    }
    if (help) {
        io.out << usage();
        return exit_status::ok;
    }
    return std::nullopt;
}

}  // namespace ameoto::client
