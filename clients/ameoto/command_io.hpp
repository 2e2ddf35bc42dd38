// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What a subcommand gets besides its words: where to print and the environment to read, passed in
// so tests can run subcommands in-process and look at exactly what they printed.
//
// Interface:
//   CommandIo io{process_environment(), std::cout, std::cerr};
//   int status = run_send(words, io);   // words: everything after "ameoto send"

#include <ostream>
#include <string>
#include <vector>

#include "clients/ameoto/target.hpp"

namespace ameoto::client {

struct CommandIo {
    Environment environment;
    std::ostream& out;   // results: replies, status fields
    std::ostream& err;   // diagnostics, prefixed "ameoto <command>: "
};

using CommandWords = std::vector<std::string>;

}  // namespace ameoto::client
