// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto send [--host H] [--port P] [--types TAGS] [--wait SECONDS] ADDRESS [ARGS...]`:
// one OSC message to the server, then its replies printed one per line (reply_format.hpp).
//
// Interface:
//   ParsedSend p = parse_send(words, environment);   // p.error: usage error; p.help: print send_usage()
//   int status = run_send(words, io);                // parse + send + wait; exit_status.hpp
//
// Waiting: up to --wait seconds (default 0.5), ending early at the reply that settles it
// (expected_reply.hpp): /status.reply, /synced, /done, or a /fail for the address sent. Other
// addresses are answered only when refused, so for them the whole --wait is spent listening for
// a /fail; --wait 0 sends and returns at once (and so cannot see a /fail).
// Exit: 0 no /fail came back; 1 a /fail came back; 2 usage error, nothing sent; 3 not sent (bad
// host, socket error, or nothing listening on the port, which this machine reports at once).
// A known reply that does not come within --wait is reported on stderr but does not change the
// exit status: only a /fail does.

#include <optional>
#include <string>
#include <vector>

#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/target.hpp"

namespace ameoto::client {

constexpr double default_send_wait_s = 0.5;
constexpr double max_send_wait_s = 3600.0;

struct SendOptions {
    Target target;
    std::optional<std::string> types;   // --types; nullopt: infer each argument's type
    double wait_s = default_send_wait_s;
    bool tcp = false;                   // --tcp: over TCP to the server's --tcp-port (given with --port)
    std::string address;
    std::vector<std::string> words;     // the message's arguments as typed
};

struct ParsedSend {
    SendOptions options;
    bool help = false;
    std::string error;
};

ParsedSend parse_send(const CommandWords& words, const Environment& environment);
int run_send(const CommandWords& words, const CommandIo& io);

}  // namespace ameoto::client
