// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --peers: the other nodes of a scene, for the node that conducts them (docs/nodes.md). Every command
// this node accepts that changes the sound is sent on to each peer in a bundle timetagged --peer-latency
// ahead (or at the command's own timetag when that is later), and this node applies it at the same
// timetag, so all nodes change at the same sample (their audio clocks map timetags to samples to the
// sample: cycle_clock.hpp). Each peer is asked for /status every 250 ms; one silent for 1.5 s is
// reported (/notice peers, the log) and the others play on; when it answers again (or for the first
// time) it is sent the current rain rate, wind and listener, timed like any command, and so joins.
//
// Interface:
//   PeerSet peers(endpoints, latency_s, replies);    peers.send_through(udp);
//   peers.empty()  peers.is_peer(sender)  peers.latency_s()
//   peers.forward(message, at_unix_s, on_block);     // at_unix_s: the bundle's timetag; nullopt: untimed;
//                                                    // on_block: it is a block start here (/nodes/block added)
//   peers.answered(sender, status_args, record, now) // a /status.reply: true when it came from a peer
//   peers.tick(now)                                  // every 250 ms: ask each peer; report the silent
//   peers.nodes_reply(own_status, now)               // /nodes.reply's arguments (docs/PROTOCOL.md)
//
// Thread: the control thread only. now: CLOCK_REALTIME seconds (the timetags' clock).

#include <boost/asio/ip/udp.hpp>

#include <optional>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "server/osc/peer.hpp"

namespace ameoto {

class Replies;
class SceneRecord;
class UdpEndpoint;

class PeerSet {
public:
    static constexpr double ask_every_s = 0.25;
    static constexpr double silent_after_s = 1.5;   // + one ask interval: reported within 2 s

    PeerSet(std::vector<boost::asio::ip::udp::endpoint> peers, double latency_s, Replies& replies);
    void send_through(UdpEndpoint& udp) { udp_ = &udp; }

    bool empty() const { return nodes_.empty(); }
    bool is_peer(const Peer& sender) const { return find(sender) != nullptr; }
    double latency_s() const { return latency_s_; }

    void forward(const protocol::DecodedMessage& message, std::optional<double> at_unix_s, bool on_block = false);
    bool answered(const Peer& sender, const std::vector<protocol::OscArgument>& status, const SceneRecord& record, double now_s);
    void tick(double now_s);
    std::vector<protocol::OscArgument> nodes_reply(const std::vector<protocol::OscArgument>& own_status, double now_s) const;

private:
    struct Node {
        boost::asio::ip::udp::endpoint endpoint;
        std::string name;                         // osc.udp://HOST:PORT/
        bool answering = false;
        bool reported_silent = false;
        double last_answer_s = 0.0;               // 0: never
        std::vector<protocol::OscArgument> status;   // its last /status.reply
    };
    const Node* find(const Peer& sender) const;
    void send(const Node& node, const std::vector<unsigned char>& bytes);
    void bring_up(const Node& node, const SceneRecord& record, double now_s);

    std::vector<Node> nodes_;
    double latency_s_;
    double started_s_ = 0.0;
    Replies& replies_;
    UdpEndpoint* udp_ = nullptr;
};

// "osc.udp://HOST:PORT[/],..." with HOST an IP address (IPv6 in brackets): the endpoints, or an error.
std::optional<std::vector<boost::asio::ip::udp::endpoint>> parse_peers(const std::string& text, std::string& error);

}  // namespace ameoto
