// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Where a UDP sender's replies go when it named another port with /reply/port (Max's [udpsend] sends
// from a port it never listens on). Keyed by the sender's own address and port; the reply keeps the
// sender's IP address, only the port changes. Bounded: at most `capacity` senders are redirected at
// once; a new one beyond that is refused (nothing is evicted, so no client silently loses its replies).
//
// Interface:
//   ReplyPorts ports;
//   ports.redirect(sender, 7771)        // false when full and the sender is not already redirected
//   ports.restore(sender)               // replies go back to the port the sender sends from
//   ports.port_of(sender)               // 7771, or 0 when not redirected
//   ports.destination(sender)           // the endpoint a reply to `sender` goes to
//   ports.size()

#include <boost/asio/ip/udp.hpp>

#include <cstdint>
#include <map>

namespace ameoto {

class ReplyPorts {
public:
    using Endpoint = boost::asio::ip::udp::endpoint;
    static constexpr std::size_t capacity = 4096;   // as many as the server's ClientTable knows

    bool redirect(const Endpoint& sender, std::uint16_t port) {
        const auto found = ports_.find(sender);
        if (found != ports_.end()) {
            found->second = port;
            return true;
        }
        if (ports_.size() >= capacity) return false;
        ports_.emplace(sender, port);
        return true;
    }
    void restore(const Endpoint& sender) { ports_.erase(sender); }
    std::uint16_t port_of(const Endpoint& sender) const {
        const auto found = ports_.find(sender);
        return found == ports_.end() ? 0 : found->second;
    }
    Endpoint destination(const Endpoint& sender) const {
        const std::uint16_t port = port_of(sender);
        return port == 0 ? sender : Endpoint(sender.address(), port);
    }
    std::size_t size() const { return ports_.size(); }

private:
    std::map<Endpoint, std::uint16_t> ports_;
};

}  // namespace ameoto
