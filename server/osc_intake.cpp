// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/osc_intake.hpp"

#include <boost/asio/post.hpp>

#include <string>
#include <vector>

#include "protocol/address_table.hpp"
#include "protocol/receive.hpp"
#include "server/log_lines.hpp"
#include "server/osc/cheap_query.hpp"

namespace ameoto {

namespace asio = boost::asio;

bool OscIntake::bind() {
    try {
        udp_ = std::make_unique<UdpEndpoint>(io_, options_.bind, options_.port,
                                             [this](std::span<const UdpEndpoint::Datagram> batch) { on_udp_batch(batch); });
    } catch (const std::exception& e) {
        warn("cannot listen on " + options_.bind + ":" + std::to_string(options_.port) + ": " + e.what());
        return false;
    }
    if (!options_.tcp_port) return true;
    try {
        tcp_ = std::make_unique<TcpEndpoint>(
            options_.bind, *options_.tcp_port, TcpLimits{},
            [this](const unsigned char* d, std::size_t n, std::uint64_t connection) { return on_tcp_packet(d, n, connection); },
            [this](std::uint64_t connection) { asio::post(io_, [this, connection] { dispatch_->closed(Peer::over_tcp(connection)); }); });
        tcp_->set_admit([this](const boost::asio::ip::address& peer) {
            if (options_.allow.allows(peer)) return true;
            asio::post(io_, [this] { ++traffic_.refused_senders; });   // --allow: closed at once, no reply
            return false;
        });
    } catch (const std::exception& e) {
        warn("cannot listen on TCP " + options_.bind + ":" + std::to_string(*options_.tcp_port) + ": " + e.what());
        return false;
    }
    return true;
}

void OscIntake::say_where() const {
    const auto local = udp_->local_endpoint();
    if (!local.address().is_loopback())
        warn("listening on " + local.address().to_string() + ", reachable from other machines (--bind)");
    if (options_.allow.restricts()) say("answering only senders in " + options_.allow.text() + " (--allow)");
    say("listening on osc.udp://" + local.address().to_string() + ":" + std::to_string(local.port()) + "/");
    if (tcp_) say("listening on osc.tcp://" + local.address().to_string() + ":" + std::to_string(tcp_->local_endpoint().port()) + "/");
}

void OscIntake::start(PacketDispatch& dispatch, StatusReport& status) {
    dispatch_ = &dispatch;
    status_ = &status;
    if (tcp_) tcp_->start();
}

void OscIntake::close() {
    if (closed_) return;
    closed_ = true;
    if (udp_) udp_->close();
    if (tcp_) tcp_->close();   // its thread reads the bridge and the backend: joined before they go
}

void OscIntake::on_udp_batch(std::span<const UdpEndpoint::Datagram> batch) {
    for (const UdpEndpoint::Datagram& d : batch) {
        if (!options_.allow.allows(d.sender.address())) {
            ++traffic_.refused_senders;   // --allow: no reply, not even /fail
            continue;
        }
        const Peer sender = Peer::over_udp(d.sender);
        if (is_cheap_query(d.data, d.size) && (udp_backlog_.empty() || !udp_backlog_.holds_from(sender))) {
            dispatch_->handle(d.data, d.size, sender);
        } else if (!udp_backlog_.push(d.data, d.size, sender)) {
            ++traffic_.busy;
            ++traffic_.unread;
            const std::string address = protocol::packet_address(d.data, d.size);
            if (address.empty() || is_reply_address(address)) continue;   // never answer a reply (nor what is no message)
            replies_.reply(sender, "/fail", protocol::fail_arguments(address, "busy: " + std::to_string(udp_backlog_.size()) +
                                                                                  " datagrams waiting to be handled"));
        }
    }
    if (!udp_backlog_.empty() && !backlog_posted_) {
        backlog_posted_ = true;
        asio::post(io_, [this] { handle_backlog(); });
    }
}

// The oldest waiting datagrams, a bounded number per turn: then reading, timers and TCP run again.
void OscIntake::handle_backlog() {
    backlog_posted_ = false;
    if (closed_) return;
    udp_->hold_replies();
    for (int n = 0; n < backlog_per_turn && !udp_backlog_.empty(); ++n) {
        const DatagramBacklog::Waiting& d = udp_backlog_.front();
        dispatch_->handle(d.data, d.size, d.sender);
        udp_backlog_.pop();
    }
    udp_->release_replies();
    if (!udp_backlog_.empty()) {
        backlog_posted_ = true;
        asio::post(io_, [this] { handle_backlog(); });
    }
}

// On the TCP endpoint's thread: /status is answered here, from atomics only; anything else, and anything
// that touches the control thread's state, is posted to it.
bool OscIntake::on_tcp_packet(const unsigned char* d, std::size_t n, std::uint64_t connection) {
    if (is_status_request(d, n)) {
        tcp_->send_here(connection, protocol::encode_message("/status.reply", status_->arguments()));
        asio::post(io_, [this, connection] { replies_.know(Peer::over_tcp(connection)); });   // gets /notice
        return true;
    }
    asio::post(io_, [this, connection, bytes = std::vector<unsigned char>(d, d + n)] {
        dispatch_->handle(bytes.data(), bytes.size(), Peer::over_tcp(connection));
        tcp_->handled(connection);   // at most TcpLimits::max_unhandled wait per connection
    });
    return false;
}

}  // namespace ameoto
