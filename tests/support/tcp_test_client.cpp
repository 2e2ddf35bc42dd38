// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/tcp_test_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include "tests/support/timing_scale.hpp"

namespace ameoto::test {

TcpTestClient::TcpTestClient(int port) {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ < 0 || connect(fd_, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
        if (fd_ >= 0) close(fd_);
        throw std::runtime_error("cannot connect to 127.0.0.1:" + std::to_string(port) + " over TCP");
    }
}

TcpTestClient::~TcpTestClient() { close(fd_); }

std::vector<unsigned char> TcpTestClient::framed(const std::vector<unsigned char>& packet) {
    const auto n = static_cast<std::uint32_t>(packet.size());
    std::vector<unsigned char> out(4 + packet.size());
    for (int i = 0; i < 4; ++i) out[static_cast<std::size_t>(i)] = static_cast<unsigned char>(n >> (24 - 8 * i));
    std::copy(packet.begin(), packet.end(), out.begin() + 4);
    return out;
}

void TcpTestClient::send_bytes(const std::vector<unsigned char>& bytes) { ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }

std::size_t TcpTestClient::offer_bytes(const std::vector<unsigned char>& bytes) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    return n > 0 ? static_cast<std::size_t>(n) : 0;   // EAGAIN: the send buffer is full, the server not reading
}

void TcpTestClient::discard_received() {
    unsigned char sink[65536];
    while (recv(fd_, sink, sizeof sink, MSG_DONTWAIT) > 0) {}
}

void TcpTestClient::send(const std::string& address, const std::vector<protocol::OscArgument>& args) {
    send_bytes(framed(protocol::encode_message(address, args)));
}

std::optional<protocol::DecodedMessage> TcpTestClient::receive(std::chrono::milliseconds timeout) {
    return receive_until(std::chrono::steady_clock::now() + scaled(timeout));
}

std::optional<protocol::DecodedMessage> TcpTestClient::receive_until(std::chrono::steady_clock::time_point end) {
    unsigned char size[4];
    if (!read_exactly(size, 4, end)) return std::nullopt;
    const std::uint32_t n = (std::uint32_t{size[0]} << 24) | (std::uint32_t{size[1]} << 16) | (std::uint32_t{size[2]} << 8) | size[3];
    std::vector<unsigned char> body(n);
    if (!read_exactly(body.data(), n, end)) return std::nullopt;
    auto p = protocol::decode_packet(body.data(), body.size());
    if (!p.error.empty() || p.messages.empty()) return std::nullopt;
    return p.messages.front();
}

std::optional<protocol::DecodedMessage> TcpTestClient::request(const std::string& address, const std::vector<protocol::OscArgument>& args,
                                                               const std::string& reply, std::chrono::milliseconds timeout) {
    send(address, args);
    const auto end = std::chrono::steady_clock::now() + scaled(timeout);
    while (std::chrono::steady_clock::now() < end) {
        auto m = receive_until(end);
        if (!m) return std::nullopt;
        if (m->address == reply) return m;
    }
    return std::nullopt;
}

bool TcpTestClient::closed_by_server(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + scaled(timeout);
    unsigned char sink[4096];
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
        if (left.count() <= 0) return false;
        pollfd p{fd_, POLLIN, 0};
        if (poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
        if (recv(fd_, sink, sizeof sink, 0) <= 0) return true;
    }
}

bool TcpTestClient::read_exactly(unsigned char* out, std::size_t n, std::chrono::steady_clock::time_point end) {
    for (std::size_t got = 0; got < n;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
        pollfd p{fd_, POLLIN, 0};
        if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
        const ssize_t r = recv(fd_, out + got, n - got, 0);
        if (r <= 0) return false;
        got += static_cast<std::size_t>(r);
    }
    return true;
}

}  // namespace ameoto::test
