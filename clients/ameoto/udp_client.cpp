// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/udp_client.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ameoto::client {
namespace {

struct AddressList {
    addrinfo* head = nullptr;
    ~AddressList() {
        if (head) freeaddrinfo(head);
    }
};

}  // namespace

std::unique_ptr<UdpClient> UdpClient::open(const Target& target, std::string& error, Transport transport) {
    const bool stream = transport == Transport::tcp;
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = stream ? SOCK_STREAM : SOCK_DGRAM;
    hints.ai_protocol = stream ? IPPROTO_TCP : IPPROTO_UDP;
    AddressList list;
    const std::string port = std::to_string(target.port);
    if (const int rc = getaddrinfo(target.host.c_str(), port.c_str(), &hints, &list.head); rc != 0) {
        error = "cannot resolve host '" + target.host + "': " + gai_strerror(rc);
        return nullptr;
    }
    const addrinfo* chosen = list.head;
    for (const addrinfo* a = list.head; a; a = a->ai_next) {
        if (a->ai_family == AF_INET) {
            chosen = a;
            break;
        }
    }
    const int fd = ::socket(chosen->ai_family, chosen->ai_socktype | SOCK_CLOEXEC, chosen->ai_protocol);
    if (fd < 0) {
        error = std::string("cannot open a ") + (stream ? "TCP" : "UDP") + " socket: " + std::strerror(errno);
        return nullptr;
    }
    if (::connect(fd, chosen->ai_addr, chosen->ai_addrlen) != 0) {
        error = "cannot reach " + target.describe() + (stream ? " over TCP" : "") + ": " + std::strerror(errno) +
                (stream && errno == ECONNREFUSED ? " (is ameotod running with --tcp-port?)" : "");
        ::close(fd);
        return nullptr;
    }
    return std::unique_ptr<UdpClient>(new UdpClient(fd, stream));
}

UdpClient::~UdpClient() { ::close(fd_); }

bool UdpClient::send(const std::vector<unsigned char>& packet, std::string& error) {
    std::vector<unsigned char> bytes;
    if (stream_) {
        const auto n = static_cast<std::uint32_t>(packet.size());
        bytes = {static_cast<unsigned char>(n >> 24), static_cast<unsigned char>(n >> 16), static_cast<unsigned char>(n >> 8),
                 static_cast<unsigned char>(n)};
    }
    bytes.insert(bytes.end(), packet.begin(), packet.end());
    ssize_t sent = -1;
    do {
        sent = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    } while (sent < 0 && errno == EINTR);
    if (sent < 0) {
        error = std::strerror(errno);
        return false;
    }
    if (static_cast<std::size_t>(sent) != bytes.size()) {
        error = "only " + std::to_string(sent) + " of " + std::to_string(bytes.size()) + " bytes went out";
        return false;
    }
    return true;
}

// One wait for the socket to become readable, bounded by the deadline: ready (read now), again (a
// signal or a poll slice ended: check the deadline and wait again), or failed (r says timeout or error).
UdpClient::Wait UdpClient::wait_readable(Deadline deadline, Received& r) const {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
        r.outcome = Received::Outcome::timeout;
        return Wait::failed;
    }
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 60'000)));
    if (ready < 0 && errno == EINTR) return Wait::again;
    if (ready < 0) {
        r.outcome = Received::Outcome::error;
        r.error = std::strerror(errno);
        return Wait::failed;
    }
    return ready == 0 ? Wait::again : Wait::ready;
}

Received UdpClient::receive(Deadline deadline) {
    if (stream_) return receive_packet(deadline);
    Received r;
    for (;;) {
        const Wait w = wait_readable(deadline, r);
        if (w == Wait::again) continue;
        if (w == Wait::failed) return r;
        // POLLERR (a pending ICMP error) also lands here: recv reports it as errno.
        r.bytes.resize(65536);
        const ssize_t n = ::recv(fd_, r.bytes.data(), r.bytes.size(), MSG_DONTWAIT);
        if (n >= 0) {
            r.bytes.resize(static_cast<std::size_t>(n));
            r.outcome = Received::Outcome::datagram;
            return r;
        }
        if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
        r.bytes.clear();
        r.outcome = errno == ECONNREFUSED ? Received::Outcome::refused : Received::Outcome::error;
        r.error = std::strerror(errno);
        return r;
    }
}

Received UdpClient::receive_packet(Deadline deadline) {
    Received r;
    for (;;) {
        if (stream_bytes_.size() >= 4) {
            const std::size_t size = (std::size_t{stream_bytes_[0]} << 24) | (std::size_t{stream_bytes_[1]} << 16) |
                                     (std::size_t{stream_bytes_[2]} << 8) | std::size_t{stream_bytes_[3]};
            if (stream_bytes_.size() >= 4 + size) {
                r.bytes.assign(stream_bytes_.begin() + 4, stream_bytes_.begin() + 4 + static_cast<std::ptrdiff_t>(size));
                stream_bytes_.erase(stream_bytes_.begin(), stream_bytes_.begin() + 4 + static_cast<std::ptrdiff_t>(size));
                r.outcome = Received::Outcome::datagram;
                return r;
            }
        }
        const Wait w = wait_readable(deadline, r);
        if (w == Wait::again) continue;
        if (w == Wait::failed) return r;
        unsigned char chunk[65536];
        const ssize_t n = ::recv(fd_, chunk, sizeof chunk, MSG_DONTWAIT);
        if (n > 0) {
            stream_bytes_.insert(stream_bytes_.end(), chunk, chunk + n);
            continue;
        }
        if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
        r.outcome = n == 0 || errno == ECONNRESET ? Received::Outcome::refused : Received::Outcome::error;   // closed by the server
        r.error = n == 0 ? "the server closed the connection" : std::strerror(errno);
        return r;
    }
}

}  // namespace ameoto::client
