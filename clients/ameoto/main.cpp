// SPDX-License-Identifier: GPL-3.0-or-later
// ameoto: the command-line client of ameotod. This file only dispatches: `ameoto COMMAND ...`
// runs the subcommand of that name with the words after it; each subcommand lives in its own
// files (send_command, status_command, watch_command, bench_command, render_drop,
// reference_command) and parses its own options. A new
// subcommand is one row in `commands` plus its line in general_usage() (usage.cpp).
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "clients/ameoto/bench_command.hpp"
#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/reference_command.hpp"
#include "clients/ameoto/render_drop.hpp"
#include "clients/ameoto/send_command.hpp"
#include "clients/ameoto/status_command.hpp"
#include "clients/ameoto/usage.hpp"
#include "clients/ameoto/watch_command.hpp"

namespace {

using namespace ameoto::client;

struct Subcommand {
    std::string_view name;
    int (*run)(const CommandWords& words, const CommandIo& io);
    std::string (*usage)();
};

constexpr Subcommand commands[] = {
    {"send", run_send, send_usage},
    {"status", run_status, status_usage},
    {"watch", run_watch, watch_usage},
    {"bench", run_bench, bench_usage},
    {"render", run_render, render_usage},
    {"reference", run_reference, reference_usage},
};

const Subcommand* find_command(std::string_view name) {
    for (const auto& c : commands)
        if (c.name == name) return &c;
    return nullptr;
}

int unknown_command(std::string_view name) {
    std::cerr << "ameoto: unknown command '" << name << "' (see ameoto --help)\n";
    return exit_status::usage;
}

// `ameoto help` and `ameoto help COMMAND` (`ameoto help help` is the general help too).
int help(const CommandWords& words) {
    if (words.empty() || words[0] == "help") {
        std::cout << general_usage();
        return exit_status::ok;
    }
    const Subcommand* c = find_command(words[0]);
    if (!c) return unknown_command(words[0]);
    std::cout << c->usage();
    return exit_status::ok;
}

}  // namespace

int main(int argc, char** argv) {
    const CommandWords words(argv + 1, argv + argc);
    if (words.empty()) {
        std::cerr << general_usage();
        return exit_status::usage;
    }
    const std::string& first = words[0];
    const CommandWords rest(words.begin() + 1, words.end());
    if (first == "--help" || first == "-h" || first == "help") return help(rest);
    if (first == "--version") {
        std::cout << version_text();
        return exit_status::ok;
    }
    const Subcommand* command = find_command(first);
    if (!command) {
        if (first.starts_with("-")) {
            std::cerr << "ameoto: unknown option '" << first << "': options come after the command (see ameoto --help)\n";
            return exit_status::usage;
        }
        return unknown_command(first);
    }
    const CommandIo io{process_environment(), std::cout, std::cerr};
    return command->run(rest, io);
}
