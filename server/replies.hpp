// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Whom the server answers, and how a reply gets there: the senders it knows (each by a small index
// that a command carries to the audio thread and back), /reply/port's redirections, UDP or TCP, and
// /notice to every sender it knows.
//
// Interface:
//   Replies replies;
//   replies.send_through(udp, tcp);               // once the ports are bound (tcp may be null)
//   replies.reply(peer, "/done", {...});          // every reply passes here, /reply/port applies to all
//   std::uint16_t i = replies.know(peer);         // from now on it gets /notice; the index names it
//   replies.peer(i)                               // whom index i names (the oldest is reused past 4096)
//   replies.notice("jack", "the JACK server went away ...");   // /notice source text to all it knows
//   replies.set_reply_port(peer, port);           // /reply/port PORT: /done, or /fail with the reason
//   replies.reply_port_of(peer)                   // the redirected port, 0 when none (the query's answer)
//
// Thread: the control thread only (the TCP endpoint's thread sends its own /status replies itself).

#include <cstdint>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "server/osc/client_table.hpp"
#include "server/osc/peer.hpp"
#include "server/osc/reply_ports.hpp"

namespace ameoto {

class TcpEndpoint;
class UdpEndpoint;

class Replies {
public:
    void send_through(UdpEndpoint& udp, TcpEndpoint* tcp) {
        udp_ = &udp;
        tcp_ = tcp;
    }
    void reply(const Peer& to, const std::string& address, const std::vector<protocol::OscArgument>& args);
    std::uint16_t know(const Peer& sender) { return clients_.index_of(sender); }
    const Peer& peer(std::uint16_t index) const { return clients_.at(index); }
    void notice(const std::string& source, const std::string& text);
    void set_reply_port(const Peer& sender, int port);
    int reply_port_of(const Peer& peer) const;

private:
    UdpEndpoint* udp_ = nullptr;
    TcpEndpoint* tcp_ = nullptr;
    ClientTable<Peer> clients_;
    ReplyPorts reply_ports_;   // /reply/port: UDP senders whose replies go to another port
};

}  // namespace ameoto
