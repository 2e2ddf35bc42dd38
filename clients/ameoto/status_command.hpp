// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto status [--host H] [--port P] [--json]`: sends /status and prints /status.reply, one
// field per line with its name and unit, or as one JSON object (status_report.hpp has the fields).
//
// Interface:
//   int status = run_status(words, io);   // words: everything after "ameoto status"
//
// Waits up to 2 s. Exit: 0 printed; 1 no reply (timed out, or nothing listens on the port, which
// this machine reports at once), a /fail, or a reply of the wrong shape; 2 usage error;
// 3 not sent (bad host, socket error).

#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

constexpr double status_timeout_s = 2.0;

int run_status(const CommandWords& words, const CommandIo& io);

}  // namespace ameoto::client
