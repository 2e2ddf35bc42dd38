// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A UDP port on 127.0.0.1 that was free a moment ago, for a program that takes a port number
// (oscdump). The kernel picks it (bind to port 0), so two tests never pick the same one at once.
//
// Interface:
//   int port = free_udp_port();   // std::runtime_error when no socket can be bound

namespace ameoto::test {

int free_udp_port();

}  // namespace ameoto::test
