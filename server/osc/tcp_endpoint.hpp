// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// OSC over TCP on a thread of its own, for rigs that cannot lose a message and for the monitor that
// must get through a UDP flood: OSC 1.0 stream framing (each packet preceded by its size as a
// big-endian int32), replies on the same connection.
//
// Interface:
//   TcpEndpoint tcp(address, port, limits, [](const unsigned char* data, std::size_t size,
//                                             std::uint64_t connection) { ...; return done_now; },   // throws on bind error
//                   [](std::uint64_t connection) { ... });                             // it closed
//   tcp.handled(connection);       // any thread: a packet the receiver handed on (returned false) is done
//   tcp.set_admit([](const address& peer) { return allowed; });   // --allow: others are closed at once
//   tcp.start();                   // the endpoint's thread runs from here: callbacks run on it
//   tcp.send(connection, bytes);   // from any thread; framed; ignored when that connection has gone
//   tcp.send_here(connection, bytes);   // the same, from a callback (on the endpoint's thread)
//   tcp.local_endpoint();          // the bound address and port (for --tcp-port 0)
//   tcp.close();                   // closes every connection and joins the thread
//
// Why a thread of its own (docs/reliability.md, "Load"): under a flood the control thread wants all
// the CPU it can get, and the kernel lets it wait its turn behind every other busy thread; a thread
// that sleeps until a request arrives is woken at once. The receiver runs on this thread: it may
// answer what it can answer safely there (ameotod: /status, from atomics) and must hand the rest to
// the control thread. What it hands on is bounded: once `max_unhandled` packets of a connection wait
// for handled(), that connection is not read until they are done (TCP's flow control then slows the
// client), so a client flooding over TCP cannot make the server's memory grow.
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
#include <thread>
#include <vector>

namespace ameoto {

struct TcpLimits {
    std::size_t max_connections = 16;
    std::size_t max_packet = 65536;          // the same bound as a UDP datagram
    std::size_t max_pending = 1 << 20;       // bytes of replies queued for one connection
    std::size_t max_unhandled = 32;          // packets of one connection handed on and not yet handled
};

class TcpEndpoint {
public:
    // Returns true when done with the packet, false when it was handed on (then handled() follows).
    using Receiver = std::function<bool(const unsigned char*, std::size_t, std::uint64_t connection)>;
    using Closed = std::function<void(std::uint64_t connection)>;
    using Admit = std::function<bool(const boost::asio::ip::address& peer)>;

    TcpEndpoint(const std::string& address, int port, TcpLimits limits, Receiver receiver, Closed closed);
    ~TcpEndpoint();
    void set_admit(Admit admit) { admit_ = std::move(admit); }
    void start();
    void send(std::uint64_t connection, std::vector<unsigned char> bytes);
    void send_here(std::uint64_t connection, const std::vector<unsigned char>& bytes);
    void handled(std::uint64_t connection);
    boost::asio::ip::tcp::endpoint local_endpoint() const { return local_; }
    void close();

private:
    struct Connection;
    void accept();
    void read_size(const std::shared_ptr<Connection>& c);
    void read_body(const std::shared_ptr<Connection>& c, std::size_t size);
    void write(const std::shared_ptr<Connection>& c);
    void drop(const std::shared_ptr<Connection>& c);

    void close_here();

    boost::asio::io_context io_;
    boost::asio::ip::tcp::acceptor acceptor_;
    boost::asio::ip::tcp::endpoint local_;
    Admit admit_;
    TcpLimits limits_;
    Receiver receiver_;
    Closed closed_;
    std::map<std::uint64_t, std::shared_ptr<Connection>> connections_;
    std::uint64_t next_id_ = 1;
    std::thread thread_;
};

}  // namespace ameoto
