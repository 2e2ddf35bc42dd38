// SPDX-License-Identifier: GPL-3.0-or-later
// How many datagrams a second the control thread's UDP path takes under a flood, the batched
// endpoint (server/osc/udp_endpoint.hpp: recvmmsg in, sendmmsg out) against its predecessor (one
// receive and one send per datagram), in the same run. Not part of the pass/fail suite.
//
// Each path runs on its own io_context thread; a sender thread floods it over loopback with
// /rain/rate as fast as it can (sendmmsg, 64 a call) for SECONDS. Every datagram read is decoded and
// validated (protocol::receive_packet) and answered `/fail /rain/rate busy: command queue full`, as
// ameotod answers a flood its command queue cannot take. Printed per path: datagrams handled per
// wall second, and per CPU second of the control thread (the figure that does not depend on what
// else the machine runs), then the ratio batched / one-by-one. A third path only reads and sets the
// datagrams aside (ameotod's backlog, server/osc/datagram_backlog.hpp), the rate at which a /status
// queued behind a flood is reached. Rounds alternate the paths; the medians are printed last.
//
// Usage: build/tests/udp_receive_bench [SECONDS [ROUNDS]]   (default 2 s, 3 rounds)

#include <arpa/inet.h>
#include <netinet/in.h>
#include <pthread.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/post.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "protocol/receive.hpp"
#include "server/osc/datagram_backlog.hpp"
#include "server/osc/udp_endpoint.hpp"

namespace {

namespace asio = boost::asio;
using Endpoint = asio::ip::udp::endpoint;
using ameoto::protocol::OscArgument;

// The endpoint as it was before batching: one async completion, then up to 256 more datagrams read
// one receive_from each, each reply its own send_to.
class OneByOneEndpoint {
public:
    using Receiver = std::function<void(const unsigned char*, std::size_t, const Endpoint&)>;
    OneByOneEndpoint(asio::io_context& io, Receiver receiver) : socket_(io), receiver_(std::move(receiver)) {
        socket_.open(asio::ip::udp::v4());
        socket_.bind(Endpoint(asio::ip::address_v4::loopback(), 0));
        boost::system::error_code ignored;
        socket_.set_option(asio::socket_base::receive_buffer_size(1 << 20), ignored);
        socket_.non_blocking(true);
        receive();
    }
    void send(const std::vector<unsigned char>& bytes, const Endpoint& to) {
        boost::system::error_code ignored;
        socket_.send_to(asio::buffer(bytes), to, 0, ignored);
    }
    int port() const { return socket_.local_endpoint().port(); }
    void close() {
        boost::system::error_code ignored;
        socket_.close(ignored);
    }

private:
    void receive() {
        socket_.async_receive_from(asio::buffer(buffer_), sender_, [this](const boost::system::error_code& ec, std::size_t size) {
            if (ec == asio::error::operation_aborted) return;
            if (!ec) {
                receiver_(buffer_.data(), size, sender_);
                for (int more = 0; more < 256 && socket_.is_open(); ++more) {
                    boost::system::error_code again;
                    const std::size_t n = socket_.receive_from(asio::buffer(buffer_), sender_, 0, again);
                    if (again) break;
                    receiver_(buffer_.data(), n, sender_);
                }
            }
            if (socket_.is_open()) receive();
        });
    }
    asio::ip::udp::socket socket_;
    Receiver receiver_;
    std::array<unsigned char, 65536> buffer_{};
    Endpoint sender_;
};

struct Result {
    std::uint64_t handled = 0;
    double wall_s = 0.0, cpu_s = 0.0;
    double per_wall_second() const { return static_cast<double>(handled) / wall_s; }
    double per_cpu_second() const { return static_cast<double>(handled) / cpu_s; }
};

double thread_cpu_seconds(pthread_t thread) {
    clockid_t clock;
    pthread_getcpuclockid(thread, &clock);
    timespec t{};
    clock_gettime(clock, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Sends /rain/rate to `port` as fast as the kernel takes it until `stop`.
void flood(int port, const std::atomic<bool>& stop) {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    constexpr std::size_t n = 64;
    std::vector<std::vector<unsigned char>> bytes;
    std::array<iovec, n> vectors{};
    std::array<mmsghdr, n> headers{};
    for (std::size_t i = 0; i < n; ++i) {
        bytes.push_back(ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(static_cast<float>(i % 50))}));
        vectors[i] = {bytes[i].data(), bytes[i].size()};
        headers[i].msg_hdr.msg_iov = &vectors[i];
        headers[i].msg_hdr.msg_iovlen = 1;
        headers[i].msg_hdr.msg_name = &to;
        headers[i].msg_hdr.msg_namelen = sizeof to;
    }
    while (!stop.load(std::memory_order_relaxed)) sendmmsg(fd, headers.data(), n, 0);
    close(fd);
}

// The work ameotod does for a datagram it must refuse busy: decode, validate, encode the /fail.
template <typename Send>
void handle(const unsigned char* data, std::size_t size, const Endpoint& from, const ameoto::protocol::ProtocolContext& context,
            std::uint64_t& handled, Send&& send) {
    const auto packet = ameoto::protocol::receive_packet(data, size, context);
    for (const auto& m : packet.messages)
        send(ameoto::protocol::encode_message("/fail", ameoto::protocol::fail_arguments(m.message.address, "busy: command queue full")), from);
    ++handled;
}

template <typename MakeEndpoint>
Result run(double seconds, MakeEndpoint make_endpoint) {
    asio::io_context io;
    ameoto::protocol::ProtocolContext context;
    Result r;
    auto [port, close_endpoint] = make_endpoint(io, context, r.handled);
    std::atomic<bool> stop{false};
    std::thread control([&] { io.run(); });
    const double cpu0 = thread_cpu_seconds(control.native_handle());
    const auto t0 = std::chrono::steady_clock::now();
    std::thread sender(flood, port, std::cref(stop));
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    // Read the count and the clocks on the control thread itself, between two handlers.
    asio::post(io, [&] {
        r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r.cpu_s = thread_cpu_seconds(pthread_self()) - cpu0;
        close_endpoint();
        io.stop();
    });
    control.join();
    stop = true;
    sender.join();
    return r;
}

Result run_one_by_one(double seconds) {
    std::unique_ptr<OneByOneEndpoint> endpoint;
    return run(seconds, [&](asio::io_context& io, const ameoto::protocol::ProtocolContext& context, std::uint64_t& handled) {
        endpoint = std::make_unique<OneByOneEndpoint>(io, [&](const unsigned char* d, std::size_t n, const Endpoint& from) {
            handle(d, n, from, context, handled, [&](const std::vector<unsigned char>& b, const Endpoint& to) { endpoint->send(b, to); });
        });
        return std::pair<int, std::function<void()>>{endpoint->port(), [&] { endpoint->close(); }};
    });
}

Result run_batched(double seconds) {
    std::unique_ptr<ameoto::UdpEndpoint> endpoint;
    return run(seconds, [&](asio::io_context& io, const ameoto::protocol::ProtocolContext& context, std::uint64_t& handled) {
        endpoint = std::make_unique<ameoto::UdpEndpoint>(io, "127.0.0.1", 0, [&](std::span<const ameoto::UdpEndpoint::Datagram> batch) {
            for (const auto& d : batch)
                handle(d.data, d.size, d.sender, context, handled,
                       [&](const std::vector<unsigned char>& b, const Endpoint& to) { endpoint->send(b, to); });
        });
        return std::pair<int, std::function<void()>>{endpoint->local_endpoint().port(), [&] { endpoint->close(); }};
    });
}

// What ameotod does with the bulk of a flood as it reads it: copied into the backlog (and, here, let
// go at once), so a /status behind it in the socket's queue is reached at this rate.
Result run_set_aside(double seconds) {
    std::unique_ptr<ameoto::UdpEndpoint> endpoint;
    ameoto::DatagramBacklog backlog(8192, 2 << 20);
    return run(seconds, [&](asio::io_context& io, const ameoto::protocol::ProtocolContext&, std::uint64_t& handled) {
        endpoint = std::make_unique<ameoto::UdpEndpoint>(io, "127.0.0.1", 0, [&](std::span<const ameoto::UdpEndpoint::Datagram> batch) {
            for (const auto& d : batch) {
                backlog.push(d.data, d.size, ameoto::Peer::over_udp(d.sender));
                ++handled;
            }
            while (!backlog.empty()) backlog.pop();
        });
        return std::pair<int, std::function<void()>>{endpoint->local_endpoint().port(), [&] { endpoint->close(); }};
    });
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 2.0;
    const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
    if (seconds <= 0.0 || rounds < 1) {
        std::fprintf(stderr, "usage: udp_receive_bench [SECONDS > 0 [ROUNDS >= 1]]\n");
        return 2;
    }
    std::printf("flood of /rain/rate over loopback, each datagram decoded, validated and answered /fail busy; %.1f s per path, %d rounds\n",
                seconds, rounds);
    std::printf("%-5s %-11s %10s %14s %18s\n", "round", "path", "handled", "datagrams/s", "per CPU second");
    std::vector<double> old_wall, new_wall, old_cpu, new_cpu, aside_cpu;
    for (int round = 1; round <= rounds; ++round) {
        const Result a = run_one_by_one(seconds);
        const Result b = run_batched(seconds);
        const Result c = run_set_aside(seconds);
        std::printf("%-5d %-11s %10llu %14.0f %18.0f\n", round, "one-by-one", static_cast<unsigned long long>(a.handled), a.per_wall_second(),
                    a.per_cpu_second());
        std::printf("%-5d %-11s %10llu %14.0f %18.0f   (batched / one-by-one: %.2f per second, %.2f per CPU second)\n", round, "batched",
                    static_cast<unsigned long long>(b.handled), b.per_wall_second(), b.per_cpu_second(), b.per_wall_second() / a.per_wall_second(), b.per_cpu_second() / a.per_cpu_second());
        std::printf("%-5d %-11s %10llu %14.0f %18.0f   (read and set aside, not handled: what reaches a /status behind the flood)\n", round,
                    "set aside", static_cast<unsigned long long>(c.handled), c.per_wall_second(), c.per_cpu_second());
        aside_cpu.push_back(c.per_cpu_second());
        old_wall.push_back(a.per_wall_second());
        new_wall.push_back(b.per_wall_second());
        old_cpu.push_back(a.per_cpu_second());
        new_cpu.push_back(b.per_cpu_second());
    }
    std::printf("median: one-by-one %.0f/s (%.0f per CPU s), batched %.0f/s (%.0f per CPU s); ratio %.2f per second, %.2f per CPU second\n",
                median(old_wall), median(old_cpu), median(new_wall), median(new_cpu), median(new_wall) / median(old_wall),
                median(new_cpu) / median(old_cpu));
    std::printf("median: read and set aside %.0f per CPU s (%.2f times one-by-one's full handling)\n", median(aside_cpu),
                median(aside_cpu) / median(old_cpu));
    return 0;
}
