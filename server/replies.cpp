// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/replies.hpp"

#include "protocol/address_table.hpp"
#include "server/osc/tcp_endpoint.hpp"
#include "server/osc/udp_endpoint.hpp"

namespace ameoto {

void Replies::reply(const Peer& to, const std::string& address, const std::vector<protocol::OscArgument>& args) {
    const auto bytes = protocol::encode_message(address, args);
    // Every reply passes here, so a /reply/port redirect covers them all (/notify's, /notice, /synced).
    if (to.transport == Peer::Transport::udp) udp_->send(bytes, reply_ports_.destination(to.udp));
    else if (tcp_) tcp_->send(to.tcp, bytes);
}

// A fault (or its end) that no request asked about: /notice source text to every sender the server knows
// (the last 4096 that sent /status or a command). docs/PROTOCOL.md lists the sources.
void Replies::notice(const std::string& source, const std::string& text) {
    const std::vector<protocol::OscArgument> args{protocol::OscArgument::from_string(source), protocol::OscArgument::from_string(text)};
    for (std::size_t i = 0; i < clients_.size(); ++i) reply(clients_.at(static_cast<std::uint16_t>(i)), "/notice", args);
}

// /reply/port PORT: this sender's later replies go to its IP address at PORT (0: its own port again).
// The /done is the first reply to take the new way, so a patch knows its receiver hears the server.
void Replies::set_reply_port(const Peer& sender, int port) {
    if (sender.transport != Peer::Transport::udp) {
        reply(sender, "/fail", protocol::fail_arguments("/reply/port", "a TCP client's replies always come back on its connection"));
        return;
    }
    if (port == 0) {
        reply_ports_.restore(sender.udp);
    } else if (!reply_ports_.redirect(sender.udp, static_cast<std::uint16_t>(port))) {
        reply(sender, "/fail", protocol::fail_arguments("/reply/port", "too many redirected senders: at most " +
                                                                           std::to_string(ReplyPorts::capacity) +
                                                                           " (/reply/port 0 frees a sender's place)"));
        return;
    }
    know(sender);   // known from now on: it gets /notice like any client that sent a command
    reply(sender, "/done", {protocol::OscArgument::from_string("/reply/port")});
}

int Replies::reply_port_of(const Peer& peer) const {
    return peer.transport == Peer::Transport::udp ? reply_ports_.port_of(peer.udp) : 0;
}

}  // namespace ameoto
