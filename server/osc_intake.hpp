// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Where packets come in, and in what order they are handled: the UDP port (batches read on the
// control thread) and the TCP port (its own thread), --allow, and under a flood the cheap queries
// first while everything else waits in a bounded backlog (docs/reliability.md, "Load").
//
// Interface:
//   OscIntake intake(io, options, replies, traffic);
//   if (!intake.bind()) return 1;      // the ports, or says why; nothing is read before the loop runs
//   intake.udp()  intake.tcp()         // for Replies::send_through (tcp: null without --tcp-port)
//   intake.say_where();                // the "listening on osc.udp://ADDRESS:PORT/" lines (and --allow's)
//   intake.start(dispatch, status);    // hands packets on from here: the TCP thread starts
//   intake.close();                    // both ports closed (the TCP thread joined); again does nothing
//
// What happens to a UDP batch: senders outside --allow are dropped before anything else is looked
// at; a cheap query (/status, a query: server/osc/cheap_query.hpp) is answered at once unless its
// sender has datagrams waiting (a sender's messages keep their order); everything else waits in the
// backlog, handled 256 at a time with reading, timers and TCP between, so the socket is read as fast
// as the flood comes. When the backlog is full the datagram is refused /fail busy by its address,
// undecoded.
// TCP: /status is answered on the endpoint's thread from atomics (StatusReport); every other packet is
// posted to the control thread (at most TcpLimits::max_unhandled waiting per connection).
//
// Threads: everything on the control thread, but for the TCP endpoint's callbacks, which run on its
// thread and touch only the StatusReport and what they post.

#include <boost/asio/io_context.hpp>

#include <memory>
#include <span>

#include "server/options.hpp"
#include "server/osc/datagram_backlog.hpp"
#include "server/osc/tcp_endpoint.hpp"
#include "server/osc/traffic_counters.hpp"
#include "server/osc/udp_endpoint.hpp"
#include "server/packet_dispatch.hpp"
#include "server/replies.hpp"
#include "server/status.hpp"

namespace ameoto {

class OscIntake {
public:
    static constexpr int backlog_per_turn = 256;   // handled before timers, TCP and reading run again

    OscIntake(boost::asio::io_context& io, const DaemonOptions& options, Replies& replies, TrafficCounters& traffic)
        : io_(io), options_(options), replies_(replies), traffic_(traffic) {}
    OscIntake(const OscIntake&) = delete;
    OscIntake& operator=(const OscIntake&) = delete;

    bool bind();
    UdpEndpoint& udp() { return *udp_; }
    TcpEndpoint* tcp() { return tcp_.get(); }
    int udp_port() const { return udp_->local_endpoint().port(); }
    int tcp_port() const { return tcp_ ? tcp_->local_endpoint().port() : 0; }
    void say_where() const;
    void start(PacketDispatch& dispatch, StatusReport& status);
    void close();

private:
    void on_udp_batch(std::span<const UdpEndpoint::Datagram> batch);
    bool on_tcp_packet(const unsigned char* data, std::size_t size, std::uint64_t connection);   // on the TCP thread
    void handle_backlog();

    boost::asio::io_context& io_;
    const DaemonOptions& options_;
    Replies& replies_;
    TrafficCounters& traffic_;
    PacketDispatch* dispatch_ = nullptr;   // from start()
    StatusReport* status_ = nullptr;
    std::unique_ptr<UdpEndpoint> udp_;
    std::unique_ptr<TcpEndpoint> tcp_;
    // UDP datagrams read but not yet handled: 8192 is 80 ms of a 100 000/s flood; 2 MiB holds them with
    // room for large bundles.
    DatagramBacklog udp_backlog_{8192, 2 << 20};
    bool backlog_posted_ = false;
    bool closed_ = false;
};

}  // namespace ameoto
