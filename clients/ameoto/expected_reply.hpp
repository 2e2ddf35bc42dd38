// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Which reply lets `ameoto send` stop waiting before --wait runs out.
//
// Interface:
//   expected_reply("/status");                       // "/status.reply"; nullopt when none is known
//   if (ends_wait(sent_address, sent_args, reply)) stop waiting
//
// The server answers /status with /status.reply, a query (ADDRESS without its value) with ADDRESS.reply, /sync id with /synced id, and /quit with
// /done "/quit" (protocol-core.md). Everything else is answered only when refused, with
// /fail address reason, and a refused message gets that one /fail and nothing else. So the wait
// ends at the known reply (matching the /sync id and the /done address), or at a /fail naming
// the address that was sent; otherwise it runs the whole --wait for a /fail that may come.

#include <optional>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::client {

std::optional<std::string> expected_reply(const std::string& address);

bool ends_wait(const std::string& sent_address, const std::vector<protocol::OscArgument>& sent_arguments,
               const protocol::DecodedMessage& reply);

}  // namespace ameoto::client
