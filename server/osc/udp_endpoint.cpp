// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/osc/udp_endpoint.hpp"

#include <sys/socket.h>
#include <sys/uio.h>

#include <boost/asio/ip/address.hpp>

#include <array>
#include <cerrno>
#include <cstring>

namespace ameoto {

// Everything recvmmsg and sendmmsg need, allocated once. The receive area is batch_size datagrams of
// the largest size (4 MiB of address space; a page is touched only where a datagram lands), the reply
// slots keep their capacity from one batch to the next.
struct UdpEndpoint::Buffers {
    std::vector<unsigned char> storage = std::vector<unsigned char>(batch_size * max_datagram);
    std::array<iovec, batch_size> in_vectors{};
    std::array<sockaddr_storage, batch_size> in_names{};
    std::array<mmsghdr, batch_size> in_headers{};
    std::array<Datagram, batch_size> received{};

    std::array<std::vector<unsigned char>, batch_size> out_bytes;
    std::array<sockaddr_storage, batch_size> out_names{};
    std::array<socklen_t, batch_size> out_name_sizes{};
    std::array<iovec, batch_size> out_vectors{};
    std::array<mmsghdr, batch_size> out_headers{};
    std::size_t out_count = 0;
};

UdpEndpoint::UdpEndpoint(boost::asio::io_context& io, const std::string& address, int port, Receiver receiver)
    : socket_(io), receiver_(std::move(receiver)), buffers_(std::make_unique<Buffers>()) {
    const Endpoint local(boost::asio::ip::make_address(address), static_cast<unsigned short>(port));
    socket_.open(local.protocol());
    socket_.bind(local);   // throws boost::system::system_error with the reason (e.g. address in use)
    // The kernel's queue rides out the moments the control thread is not running (another process has
    // the CPU): 4 MiB, doubled by the kernel, holds about 10 000 small datagrams, 100 ms of a 100 000/s
    // flood. It costs little latency, since the endpoint reads it fast and sets the bulk aside
    // (docs/reliability.md, "Load"). The kernel caps the value at net.core.rmem_max (Debian's default,
    // 212 992 bytes, holds about 500 datagrams).
    boost::system::error_code ignored;
    socket_.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer_bytes), ignored);
    socket_.non_blocking(true);
    wait();
}

UdpEndpoint::~UdpEndpoint() = default;

void UdpEndpoint::wait() {
    // Asio re-arms the descriptor in epoll for the wait (EPOLL_CTL_MOD), so a socket that still holds
    // datagrams wakes it at once: nothing waits for a new datagram to be noticed.
    socket_.async_wait(boost::asio::socket_base::wait_read, [this](const boost::system::error_code& ec) {
        if (ec == boost::asio::error::operation_aborted || !socket_.is_open()) return;
        drain();
        if (socket_.is_open()) wait();
    });
}

// Up to max_batches_per_wake batches, each read in one recvmmsg and handed on whole; stops early once
// the socket is empty.
void UdpEndpoint::drain() {
    Buffers& b = *buffers_;
    for (int batch = 0; batch < max_batches_per_wake && socket_.is_open(); ++batch) {
        for (std::size_t i = 0; i < batch_size; ++i) {
            b.in_vectors[i] = {b.storage.data() + i * max_datagram, max_datagram};
            b.in_headers[i] = {};
            b.in_headers[i].msg_hdr.msg_iov = &b.in_vectors[i];
            b.in_headers[i].msg_hdr.msg_iovlen = 1;
            b.in_headers[i].msg_hdr.msg_name = &b.in_names[i];
            b.in_headers[i].msg_hdr.msg_namelen = sizeof(sockaddr_storage);
        }
        const int n = recvmmsg(socket_.native_handle(), b.in_headers.data(), batch_size, MSG_DONTWAIT, nullptr);
        ++counters_.receive_calls;
        if (n <= 0) return;   // EAGAIN: empty; any other error is the socket's last one, reported once
        for (int i = 0; i < n; ++i) {
            Datagram& d = b.received[static_cast<std::size_t>(i)];
            d.data = static_cast<const unsigned char*>(b.in_vectors[static_cast<std::size_t>(i)].iov_base);
            d.size = b.in_headers[static_cast<std::size_t>(i)].msg_len;
            d.sender = Endpoint();
            const socklen_t name_size = b.in_headers[static_cast<std::size_t>(i)].msg_hdr.msg_namelen;
            std::memcpy(d.sender.data(), &b.in_names[static_cast<std::size_t>(i)], name_size);
            d.sender.resize(name_size);
        }
        counters_.datagrams += static_cast<std::uint64_t>(n);
        hold_replies();
        receiver_(std::span<const Datagram>(b.received.data(), static_cast<std::size_t>(n)));
        release_replies();
        if (static_cast<std::size_t>(n) < batch_size) return;   // the socket is empty now
    }
}

void UdpEndpoint::send(const std::vector<unsigned char>& bytes, const Endpoint& to) {
    ++counters_.replies;
    if (!holding_) {
        boost::system::error_code ignored;   // a client that went away is not the server's problem
        socket_.send_to(boost::asio::buffer(bytes), to, 0, ignored);
        ++counters_.send_calls;
        return;
    }
    Buffers& b = *buffers_;
    if (b.out_count == batch_size) flush();
    const std::size_t i = b.out_count++;
    b.out_bytes[i].assign(bytes.begin(), bytes.end());   // keeps its capacity: no allocation once warm
    std::memcpy(&b.out_names[i], to.data(), to.size());
    b.out_name_sizes[i] = static_cast<socklen_t>(to.size());
}

void UdpEndpoint::release_replies() {
    holding_ = false;
    flush();
}

void UdpEndpoint::flush() {
    Buffers& b = *buffers_;
    for (std::size_t i = 0; i < b.out_count; ++i) {
        b.out_vectors[i] = {b.out_bytes[i].data(), b.out_bytes[i].size()};
        b.out_headers[i] = {};
        b.out_headers[i].msg_hdr.msg_iov = &b.out_vectors[i];
        b.out_headers[i].msg_hdr.msg_iovlen = 1;
        b.out_headers[i].msg_hdr.msg_name = &b.out_names[i];
        b.out_headers[i].msg_hdr.msg_namelen = b.out_name_sizes[i];
    }
    std::size_t sent = 0;
    while (sent < b.out_count && socket_.is_open()) {
        const int n = sendmmsg(socket_.native_handle(), b.out_headers.data() + sent, static_cast<unsigned>(b.out_count - sent), MSG_DONTWAIT);
        ++counters_.send_calls;
        // A reply that cannot leave (its client went away, the send buffer is full) is skipped, as a
        // lost datagram would be; the rest still go.
        sent += n > 0 ? static_cast<std::size_t>(n) : 1;
    }
    b.out_count = 0;
}

void UdpEndpoint::close() {
    boost::system::error_code ignored;
    socket_.close(ignored);
}

}  // namespace ameoto
