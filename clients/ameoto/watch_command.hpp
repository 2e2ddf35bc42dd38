// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto watch`: subscribe to the server's notifications (/notify 1) and show its level meters and
// load live: redrawn in place on a terminal, one line per update otherwise; Ctrl-C (or --count
// updates) unsubscribes (/notify 0) and quits.
//
// Interface:
//   int status = run_watch(words, io);   // words: everything after "ameoto watch"
//   std::string text = watch_usage();

#include <string>

#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

int run_watch(const CommandWords& words, const CommandIo& io);
std::string watch_usage();

}  // namespace ameoto::client
