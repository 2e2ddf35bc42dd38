// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/peers.hpp"

#include <boost/asio/ip/address.hpp>

#include <charconv>

#include "server/log_lines.hpp"
#include "server/osc/udp_endpoint.hpp"
#include "server/replies.hpp"
#include "server/scene_record.hpp"

namespace ameoto {

using protocol::OscArgument;

std::optional<std::vector<boost::asio::ip::udp::endpoint>> parse_peers(const std::string& text, std::string& error) {
    std::vector<boost::asio::ip::udp::endpoint> out;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t comma = text.find(',', at);
        std::string item = text.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
        at = comma == std::string::npos ? text.size() + 1 : comma + 1;
        const std::string scheme = "osc.udp://";
        if (!item.starts_with(scheme)) {
            error = "'" + item + "' is not osc.udp://HOST:PORT";
            return std::nullopt;
        }
        item = item.substr(scheme.size());
        if (item.ends_with("/")) item.pop_back();
        const std::size_t colon = item.rfind(':');
        if (colon == std::string::npos || colon == 0) {
            error = "'" + item + "' has no HOST:PORT";
            return std::nullopt;
        }
        std::string host = item.substr(0, colon);
        if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
        const std::string port_text = item.substr(colon + 1);
        int port = 0;
        const auto r = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
        if (r.ec != std::errc() || r.ptr != port_text.data() + port_text.size() || port < 1 || port > 65535) {
            error = "'" + port_text + "' is not a port 1..65535";
            return std::nullopt;
        }
        boost::system::error_code ec;
        const auto address = boost::asio::ip::make_address(host, ec);
        if (ec) {
            error = "'" + host + "' is not an IP address";
            return std::nullopt;
        }
        out.emplace_back(address, static_cast<unsigned short>(port));
    }
    if (out.size() > 15) {
        error = "at most 15 peers (16 nodes in all)";
        return std::nullopt;
    }
    return out;
}

PeerSet::PeerSet(std::vector<boost::asio::ip::udp::endpoint> peers, double latency_s, Replies& replies)
    : latency_s_(latency_s), replies_(replies) {
    for (const auto& e : peers) {
        Node n;
        n.endpoint = e;
        const std::string host = e.address().is_v6() ? "[" + e.address().to_string() + "]" : e.address().to_string();
        n.name = "osc.udp://" + host + ":" + std::to_string(e.port()) + "/";
        nodes_.push_back(std::move(n));
    }
}

const PeerSet::Node* PeerSet::find(const Peer& sender) const {
    if (sender.transport != Peer::Transport::udp) return nullptr;
    for (const Node& n : nodes_)
        if (n.endpoint == sender.udp) return &n;
    return nullptr;
}

void PeerSet::send(const Node& node, const std::vector<unsigned char>& bytes) {
    if (udp_) udp_->send(bytes, node.endpoint);
}

// The message as it came, in a bundle of its own at the agreed time. Sent to a peer that is silent too:
// a datagram to a node that is down costs nothing, and one that has just come back gets it.
void PeerSet::forward(const protocol::DecodedMessage& message, std::optional<double> at_unix_s, bool on_block) {
    const auto bytes = protocol::encode_message(message.address, message.args);
    std::vector<std::vector<unsigned char>> elements{bytes};
    if (on_block) elements.insert(elements.begin(), protocol::encode_message("/nodes/block", {}));
    const auto packet = at_unix_s ? protocol::encode_bundle(protocol::Timetag::from_unix_seconds(*at_unix_s), elements) : bytes;
    for (const Node& n : nodes_) send(n, packet);
}

bool PeerSet::answered(const Peer& sender, const std::vector<OscArgument>& status, const SceneRecord& record, double now_s) {
    Node* node = const_cast<Node*>(find(sender));
    if (!node) return false;
    if (status.size() != 16) return true;   // not the /status.reply layout: taken as no answer
    const bool joining = !node->answering;
    node->answering = true;
    node->last_answer_s = now_s;
    node->status = status;
    if (joining) {
        if (node->reported_silent) {
            say("peer " + node->name + " answers again: sent the current settings");
            replies_.notice("peers", node->name + " answers again: brought up to the current settings");
        } else {
            say("peer " + node->name + " answers: sent the current settings");
        }
        node->reported_silent = false;
        bring_up(*node, record, now_s);
    }
    return true;
}

// What a node that missed commands needs to sound as the others do: the rain rate, the wind, the
// listener and the head's orientation now in effect, in one bundle at now + latency (a scene, material
// or liquid change is not re-sent: a node runs with the same scene file, and those rebuild the scene).
// The orientation only once the head has turned: a node playing `ears` refuses any orientation, and an
// unturned head is where every node starts.
void PeerSet::bring_up(const Node& node, const SceneRecord& record, double now_s) {
    const auto& s = record.scene();
    constexpr double deg_per_rad = 180.0 / 3.14159265358979323846;
    std::vector<std::vector<unsigned char>> settings{
        protocol::encode_message("/rain/rate", {OscArgument::from_float(static_cast<float>(s.rain.rate_mm_per_h))}),
        protocol::encode_message("/rain/wind", {OscArgument::from_float(static_cast<float>(s.rain.wind_m_per_s)),
                                                OscArgument::from_float(static_cast<float>(s.rain.wind_direction_rad * deg_per_rad)),
                                                OscArgument::from_float(static_cast<float>(s.rain.gustiness))}),
        protocol::encode_message("/listener", {OscArgument::from_float(static_cast<float>(s.listener.x_m)),
                                               OscArgument::from_float(static_cast<float>(s.listener.y_m)),
                                               OscArgument::from_float(static_cast<float>(s.listener.z_m)),
                                               OscArgument::from_float(static_cast<float>(s.listener.facing_rad * deg_per_rad))})};
    const auto& head = record.orientation();
    if (head[0] != 0.0 || head[1] != 0.0 || head[2] != 0.0)
        settings.push_back(protocol::encode_message("/listener/orientation", {OscArgument::from_float(static_cast<float>(head[0] * deg_per_rad)),
                                                                              OscArgument::from_float(static_cast<float>(head[1] * deg_per_rad)),
                                                                              OscArgument::from_float(static_cast<float>(head[2] * deg_per_rad))}));
    send(node, protocol::encode_bundle(protocol::Timetag::from_unix_seconds(now_s + latency_s_), settings));
}

void PeerSet::tick(double now_s) {
    if (started_s_ == 0.0) started_s_ = now_s;
    const auto ask = protocol::encode_message("/status", {});
    for (Node& n : nodes_) {
        send(n, ask);
        const double since = now_s - (n.last_answer_s > 0.0 ? n.last_answer_s : started_s_);
        if (since < silent_after_s || n.reported_silent) continue;
        n.answering = false;
        n.reported_silent = true;
        const std::string text = n.name + (n.last_answer_s > 0.0 ? " stopped answering" : " has not answered") +
                                 "; the other nodes play on";
        warn("peer " + text);
        replies_.notice("peers", text);
    }
}

// i nodes, then for each node (this one first, as "self"): s address, i answering, f seconds since its
// last answer, f drops/s, f CPU average %, i xruns, f rain rate mm/h.
std::vector<OscArgument> PeerSet::nodes_reply(const std::vector<OscArgument>& own, double now_s) const {
    std::vector<OscArgument> out{OscArgument::from_int(static_cast<std::int32_t>(nodes_.size() + 1))};
    auto add = [&](const std::string& name, bool answering, double age, const std::vector<OscArgument>& s) {
        const bool has = s.size() == 16;
        out.push_back(OscArgument::from_string(name));
        out.push_back(OscArgument::from_int(answering ? 1 : 0));
        out.push_back(OscArgument::from_float(static_cast<float>(age)));
        out.push_back(OscArgument::from_float(has ? static_cast<float>(s[2].number) : 0.0f));
        out.push_back(OscArgument::from_float(has ? static_cast<float>(s[0].number) : 0.0f));
        out.push_back(OscArgument::from_int(has ? static_cast<std::int32_t>(s[6].integer) : 0));
        out.push_back(OscArgument::from_float(has ? static_cast<float>(s[11].number) : 0.0f));
    };
    add("self", true, 0.0, own);
    for (const Node& n : nodes_) add(n.name, n.answering, n.last_answer_s > 0.0 ? now_s - n.last_answer_s : -1.0, n.status);
    return out;
}

}  // namespace ameoto
