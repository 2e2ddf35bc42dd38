// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Whom a reply goes to: a UDP sender (its address and port) or a TCP connection (its number).
//
// Interface:
//   Peer p = Peer::over_udp(endpoint);   Peer q = Peer::over_tcp(connection_id);
//   p == q;  p.describe();   // "udp 127.0.0.1:5000", "tcp connection 3"

#include <boost/asio/ip/udp.hpp>

#include <cstdint>
#include <string>

namespace ameoto {

struct Peer {
    enum class Transport { udp, tcp } transport = Transport::udp;
    boost::asio::ip::udp::endpoint udp;   // Transport::udp
    std::uint64_t tcp = 0;                // Transport::tcp: the connection's number, never reused

    static Peer over_udp(const boost::asio::ip::udp::endpoint& e) { return Peer{Transport::udp, e, 0}; }
    static Peer over_tcp(std::uint64_t connection) { return Peer{Transport::tcp, {}, connection}; }
    bool operator==(const Peer& o) const {
        return transport == o.transport && (transport == Transport::udp ? udp == o.udp : tcp == o.tcp);
    }
    std::string describe() const {
        return transport == Transport::udp ? "udp " + udp.address().to_string() + ":" + std::to_string(udp.port())
                                           : "tcp connection " + std::to_string(tcp);
    }
};

}  // namespace ameoto
