// SPDX-License-Identifier: GPL-3.0-or-later
// The batched UDP endpoint (server/osc/udp_endpoint.hpp) over real loopback sockets: datagrams
// queued in the socket are read many per receive call, in order, each with its sender and its bytes
// intact (up to the largest datagram); replies made while a batch is handled leave together, in order.

#include "server/osc/udp_endpoint.hpp"

#include <doctest/doctest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/post.hpp>

#include <chrono>
#include <vector>

namespace {
using ameoto::UdpEndpoint;

// A plain client socket on an ephemeral loopback port.
struct Client {
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    Client() {
        sockaddr_in local{};
        local.sin_family = AF_INET;
        local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local);
        int size = 8 << 20;
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    }
    ~Client() { close(fd); }
    int port() const {
        sockaddr_in local{};
        socklen_t n = sizeof local;
        getsockname(fd, reinterpret_cast<sockaddr*>(&local), &n);
        return ntohs(local.sin_port);
    }
    void send_to(int port, const std::vector<unsigned char>& bytes) const {
        sockaddr_in to{};
        to.sin_family = AF_INET;
        to.sin_port = htons(static_cast<std::uint16_t>(port));
        to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to) == static_cast<ssize_t>(bytes.size()));
    }
    std::vector<unsigned char> receive(int timeout_ms) const {
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, timeout_ms) <= 0) return {};
        std::vector<unsigned char> b(65536);
        const ssize_t n = recv(fd, b.data(), b.size(), 0);
        b.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
        return b;
    }
};

std::vector<unsigned char> numbered(std::size_t size, std::uint32_t number) {
    std::vector<unsigned char> b(size, static_cast<unsigned char>(number * 13));
    for (int i = 0; i < 4; ++i) b[static_cast<std::size_t>(i)] = static_cast<unsigned char>(number >> (8 * i));
    return b;
}
std::uint32_t number_of(const unsigned char* b) { return b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24); }
}  // namespace

TEST_CASE("udp endpoint: a queue of datagrams is read in batches, in order, with senders and bytes intact; replies leave batched, in order") {
    boost::asio::io_context io;
    Client a, b;
    constexpr std::uint32_t each = 300;
    std::vector<std::uint32_t> from_a, from_b;
    std::size_t largest_batch = 0;
    bool intact = true;
    std::unique_ptr<UdpEndpoint> udp;
    udp = std::make_unique<UdpEndpoint>(io, "127.0.0.1", 0, [&](std::span<const UdpEndpoint::Datagram> batch) {
        largest_batch = std::max(largest_batch, batch.size());
        for (const auto& d : batch) {
            const std::uint32_t n = number_of(d.data);
            intact = intact && d.size == 40 + n % 50 && d.data[d.size - 1] == static_cast<unsigned char>(n * 13);
            (d.sender.port() == a.port() ? from_a : from_b).push_back(n);
            udp->send(std::vector<unsigned char>(d.data, d.data + 4), d.sender);   // echo the number
        }
        if (from_a.size() + from_b.size() == 2 * each) io.stop();
    });
    const int port = udp->local_endpoint().port();
    // Everything is queued in the socket before the endpoint runs: it finds a backlog.
    for (std::uint32_t i = 0; i < each; ++i) {
        a.send_to(port, numbered(40 + i % 50, i));
        b.send_to(port, numbered(40 + (each + i) % 50, each + i));
    }
    io.run_for(std::chrono::seconds(5));
    REQUIRE(from_a.size() == each);
    REQUIRE(from_b.size() == each);
    CHECK(intact);
    for (std::uint32_t i = 0; i < each; ++i) {
        CHECK(from_a[i] == i);
        CHECK(from_b[i] == each + i);
    }
    // Batches: far fewer receive and send calls than datagrams.
    CHECK(largest_batch == UdpEndpoint::batch_size);
    CHECK(udp->counters().datagrams == 2 * each);
    CHECK(udp->counters().receive_calls * 8 < udp->counters().datagrams);
    CHECK(udp->counters().replies == 2 * each);
    CHECK(udp->counters().send_calls * 8 < udp->counters().replies);
    for (std::uint32_t i = 0; i < each; ++i) {
        const auto r = a.receive(2000);
        REQUIRE(r.size() == 4);
        CHECK(number_of(r.data()) == i);
    }
}

TEST_CASE("udp endpoint: the largest datagram arrives whole; a reply outside a batch leaves at once") {
    boost::asio::io_context io;
    Client c;
    std::vector<unsigned char> got;
    UdpEndpoint udp(io, "127.0.0.1", 0, [&](std::span<const UdpEndpoint::Datagram> batch) {
        got.assign(batch[0].data, batch[0].data + batch[0].size);
        io.stop();
    });
    const auto big = numbered(65507, 7);   // the largest IPv4 UDP payload
    c.send_to(udp.local_endpoint().port(), big);
    io.run_for(std::chrono::seconds(5));
    CHECK(got == big);
    udp.send({1, 2, 3, 4}, UdpEndpoint::Endpoint(boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(c.port())));
    CHECK(c.receive(2000) == std::vector<unsigned char>{1, 2, 3, 4});
}
