// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// OSC over UDP on the control thread's io_context: receives datagrams in batches, hands each batch
// on with its senders, sends replies (in batches while a batch is being handled).
//
// Interface:
//   UdpEndpoint udp(io, address, port, [](std::span<const UdpEndpoint::Datagram> batch) {
//       for (const auto& d : batch) ... d.data, d.size, d.sender ...
//   });                          // throws on bind error
//   udp.send(bytes, sender);     // inside the batch handler: queued, sent when the batch is done
//   udp.hold_replies(); ... udp.send(...) ...; udp.release_replies();   // the same, outside a batch
//   udp.local_endpoint();        // the bound address and port (for --port 0)
//   udp.counters();              // datagrams and batches read, receive calls, replies, send calls
//
// Why batches (docs/reliability.md, "Load"): under a flood the per-datagram cost is mostly system
// calls. recvmmsg(2) reads up to `batch_size` queued datagrams in one call, and the replies a batch
// makes leave in one sendmmsg(2). A handler sees a whole batch, so it can answer cheap queries
// (/status) at once and set the rest aside (server/osc/datagram_backlog.hpp). After
// `max_batches_per_wake` batches the endpoint waits on the socket again, so timers, TCP and the
// set-aside work run between reads even while a flood lasts.
//
// Why Asio owns the socket, not liblo: liblo 0.31 binds every unicast server to the wildcard address
// (server.c: getaddrinfo(NULL, port, AI_PASSIVE)), so it cannot honour --bind 127.0.0.1, and a
// daemon that listens on every interface by default would be open to the network. liblo still
// decodes and encodes every message (protocol/osc_codec.hpp).

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace ameoto {

class UdpEndpoint {
public:
    using Endpoint = boost::asio::ip::udp::endpoint;
    struct Datagram {
        const unsigned char* data;
        std::size_t size;
        Endpoint sender;
    };
    using Receiver = std::function<void(std::span<const Datagram> batch)>;
    struct Counters {
        std::uint64_t datagrams = 0, receive_calls = 0, replies = 0, send_calls = 0;
    };

    static constexpr std::size_t batch_size = 64;
    static constexpr int max_batches_per_wake = 8;
    static constexpr std::size_t max_datagram = 65536;   // the largest UDP payload; larger is impossible
    static constexpr int receive_buffer_bytes = 4 << 20;

    UdpEndpoint(boost::asio::io_context& io, const std::string& address, int port, Receiver receiver);
    ~UdpEndpoint();
    void send(const std::vector<unsigned char>& bytes, const Endpoint& to);
    void hold_replies() { holding_ = true; }
    void release_replies();
    Endpoint local_endpoint() const { return socket_.local_endpoint(); }
    const Counters& counters() const { return counters_; }
    void close();

private:
    struct Buffers;
    void wait();
    void drain();
    void flush();
    boost::asio::ip::udp::socket socket_;
    Receiver receiver_;
    std::unique_ptr<Buffers> buffers_;   // fixed at construction: memory stays flat under any flood
    bool holding_ = false;   // replies wait in the out slots until release_replies()
    Counters counters_;
};

}  // namespace ameoto
