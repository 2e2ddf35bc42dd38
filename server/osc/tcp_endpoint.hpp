#pragma once
// OSC over TCP on the control thread's io_context, for rigs that cannot lose a message: OSC 1.0
// stream framing (each packet preceded by its size as a big-endian int32), replies on the same
// connection.
//
// Interface:
//   TcpEndpoint tcp(io, address, port, limits, [](const unsigned char* data, std::size_t size,
//                                                 std::uint64_t connection) { ... });   // throws on bind error
//   tcp.send(connection, bytes);   // framed; ignored when that connection has gone
//   tcp.local_endpoint();          // the bound address and port (for --tcp-port 0)
//   tcp.set_admit([](const address& peer) { return allowed; });   // --allow: others are closed at once
//   tcp.open_connections();  tcp.close();
//
// Bounds, so that no client can make the server misbehave: at most `max_connections` at once (one
// more is accepted and closed at once); a packet larger than `max_packet` closes its connection (the
// stream cannot be resynchronised after a bad size); replies waiting to be written to one connection
// beyond `max_pending` bytes close it (a client that does not read). A connection that closes or
// fails goes alone; the others and UDP are untouched.
// Why not SLIP (OSC 1.1): the size prefix is what liblo's TCP transport, SuperCollider and oscP5 speak.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ameoto {

struct TcpLimits {
    std::size_t max_connections = 16;
    std::size_t max_packet = 65536;          // the same bound as a UDP datagram
    std::size_t max_pending = 1 << 20;       // bytes of replies queued for one connection
};

class TcpEndpoint {
public:
    using Receiver = std::function<void(const unsigned char*, std::size_t, std::uint64_t connection)>;
    using Closed = std::function<void(std::uint64_t connection)>;
    using Admit = std::function<bool(const boost::asio::ip::address& peer)>;

    TcpEndpoint(boost::asio::io_context& io, const std::string& address, int port, TcpLimits limits, Receiver receiver,
                Closed closed);
    ~TcpEndpoint();
    void send(std::uint64_t connection, const std::vector<unsigned char>& bytes);
    boost::asio::ip::tcp::endpoint local_endpoint() const { return acceptor_.local_endpoint(); }
    std::size_t open_connections() const { return connections_.size(); }
    void set_admit(Admit admit) { admit_ = std::move(admit); }
    void close();

private:
    struct Connection;
    void accept();
    void read_size(const std::shared_ptr<Connection>& c);
    void read_body(const std::shared_ptr<Connection>& c, std::size_t size);
    void write(const std::shared_ptr<Connection>& c);
    void drop(const std::shared_ptr<Connection>& c);

    boost::asio::io_context& io_;
    boost::asio::ip::tcp::acceptor acceptor_;
    Admit admit_;
    TcpLimits limits_;
    Receiver receiver_;
    Closed closed_;
    std::map<std::uint64_t, std::shared_ptr<Connection>> connections_;
    std::uint64_t next_id_ = 1;
};

}  // namespace ameoto
