// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The exit statuses every ameoto subcommand uses, so scripts can tell the cases apart.
//
// Interface:
//   return exit_status::ok;          // 0: done, and the server refused nothing
//   return exit_status::refused;     // 1: the server answered /fail, or (status) did not answer
//   return exit_status::usage;       // 2: the command line is wrong; nothing was sent
//   return exit_status::not_sent;    // 3: the message could not be sent (host, socket, refused port)

namespace ameoto::client::exit_status {

constexpr int ok = 0;
constexpr int refused = 1;
constexpr int usage = 2;
constexpr int not_sent = 3;

}  // namespace ameoto::client::exit_status
