// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The first step every talking subcommand shares (send, status, watch): open a client to the target
// and send one message; on failure print why, after the command's prefix, to io.err.
//
// Interface:
//   auto client = open_and_send(target, Transport::udp, bytes, io, "ameoto status: ");
//   if (!client) return exit_status::not_sent;   // the reason is already printed

#include <memory>
#include <string>
#include <vector>

#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/udp_client.hpp"

namespace ameoto::client {

std::unique_ptr<UdpClient> open_and_send(const Target& target, Transport transport, const std::vector<unsigned char>& message,
                                         const CommandIo& io, const std::string& prefix);

}  // namespace ameoto::client
