// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The help texts of `ameoto` and its subcommands, and its version line.
//
// Interface:
//   std::cout << general_usage();   // ameoto --help, ameoto help
//   std::cout << send_usage();      // ameoto send --help, ameoto help send
//   std::cout << status_usage();    // ameoto status --help, ameoto help status
//   std::cout << version_text();    // "ameoto 0.1.0\n"
//
// send_usage() lists the addresses from protocol::address_table(), the same table the server
// validates with, so the help cannot drift from what this version of the protocol accepts.
// A new subcommand adds its line to general_usage() and its own *_usage().

#include <string>

namespace ameoto::client {

std::string general_usage();
std::string send_usage();
std::string status_usage();
std::string version_text();

}  // namespace ameoto::client
