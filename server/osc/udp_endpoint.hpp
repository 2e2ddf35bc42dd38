#pragma once
// OSC over UDP on the control thread's io_context: receives datagrams, hands them on with the
// sender, sends replies.
//
// Interface:
//   UdpEndpoint udp(io, address, port, [](const unsigned char* data, std::size_t size,
//                                         const udp::endpoint& sender) { ... });   // throws on bind error
//   udp.send(bytes, sender);
//   udp.local_endpoint();        // the bound address and port (for --port 0)
//
// Why Asio owns the socket, not liblo: liblo 0.31 binds every unicast server to the wildcard address
// (server.c: getaddrinfo(NULL, port, AI_PASSIVE)), so it cannot honour --bind 127.0.0.1, and a
// daemon that listens on every interface by default would be open to the network. liblo still
// decodes and encodes every message (protocol/osc_codec.hpp).

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace ameoto {

class UdpEndpoint {
public:
    using Endpoint = boost::asio::ip::udp::endpoint;
    using Receiver = std::function<void(const unsigned char*, std::size_t, const Endpoint&)>;

    UdpEndpoint(boost::asio::io_context& io, const std::string& address, int port, Receiver receiver);
    void send(const std::vector<unsigned char>& bytes, const Endpoint& to);
    Endpoint local_endpoint() const { return socket_.local_endpoint(); }
    void close();

private:
    void receive();
    boost::asio::ip::udp::socket socket_;
    Receiver receiver_;
    std::array<unsigned char, 65536> buffer_{};
    Endpoint sender_;
};

}  // namespace ameoto
