// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/osc_test_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>

#include "tests/support/timing_scale.hpp"

namespace ameoto::test {

OscTestClient::OscTestClient(int server_port) : port_(server_port) {
    fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) throw std::runtime_error("client socket");
}

OscTestClient::~OscTestClient() {
    if (fd_ >= 0) close(fd_);
}

void OscTestClient::send_raw(const std::vector<unsigned char>& bytes) {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port_));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
}

void OscTestClient::send(const std::string& address, const std::vector<protocol::OscArgument>& args) {
    send_raw(protocol::encode_message(address, args));
}

std::optional<protocol::DecodedMessage> OscTestClient::receive(std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
    unsigned char buffer[65536];
    const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
    if (n <= 0) return std::nullopt;
    auto packet = protocol::decode_packet(buffer, static_cast<std::size_t>(n));
    if (!packet.error.empty() || packet.messages.empty()) return std::nullopt;
    return packet.messages.front();
}

// A reply waited for comes after the server's work (a scene rebuilt for /material: several times
// slower under the sanitizers), so this wait stretches there (timing_scale.hpp); receive() does not.
std::optional<protocol::DecodedMessage> OscTestClient::wait_for(const std::string& reply_address, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + scaled(timeout);
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) return std::nullopt;
        auto m = receive(left);
        if (!m) return std::nullopt;
        if (m->address == reply_address) return m;
        others.push_back(std::move(*m));
    }
}

std::optional<protocol::DecodedMessage> OscTestClient::request(const std::string& address, const std::vector<protocol::OscArgument>& args,
                                                               const std::string& reply_address, std::chrono::milliseconds timeout) {
    send(address, args);
    return wait_for(reply_address, timeout);
}

}  // namespace ameoto::test
