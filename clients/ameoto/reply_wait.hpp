// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The receive loop both subcommands share: decode each datagram from the server, hand its
// messages on, stop when the handler says so or the deadline passes.
//
// Interface:
//   WaitResult w = wait_for_replies(client, deadline,
//                                   [&](const protocol::DecodedMessage& m) { ...; return stop; },
//                                   [&](const std::string& problem) { warn about a bad datagram });
//   switch (w.ending) { stopped, timed_out, refused (nothing listens), error (w.error) }
//
// A datagram that does not decode is reported and skipped, not fatal: the server might be a newer
// one, and the replies that do decode still count.

#include <functional>
#include <string>

#include "clients/ameoto/udp_client.hpp"
#include "protocol/osc_codec.hpp"

namespace ameoto::client {

struct WaitResult {
    enum class Ending { stopped, timed_out, refused, error };
    Ending ending = Ending::timed_out;
    std::string error;
};

WaitResult wait_for_replies(UdpClient& client, Deadline deadline,
                            const std::function<bool(const protocol::DecodedMessage&)>& on_message,
                            const std::function<void(const std::string&)>& on_bad_datagram);

}  // namespace ameoto::client
