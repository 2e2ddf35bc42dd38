// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A TCP OSC client for tests (OSC 1.0 stream framing: each packet preceded by its size as a big-endian
// int32), connected to ameotod's --tcp-port over loopback; every wait bounded, and timing_scale() times
// as long in the sanitized build, as OscTestClient's (timing_scale.hpp).
//
// Interface:
//   TcpTestClient c(port);                                   // throws std::runtime_error if it cannot connect
//   c.send("/status");                                       // one framed message
//   c.send_bytes(TcpTestClient::framed(packet));             // anything, for malformed or split input
//   std::size_t n = c.offer_bytes(bytes);                    // what the socket takes now, without waiting: 0 when
//                                                            // the server's flow control holds it back (a flood)
//   c.discard_received();                                    // whatever has arrived, dropped without waiting
//   auto m = c.receive(500ms);                               // the next packet's first message, or nullopt
//                                                            // (timeout, or the server closed the connection)
//   auto r = c.request("/status", {}, "/status.reply", 2s);  // send, then wait for that address (default 2 s)
//   c.closed_by_server(1s)                                   // true once the server has closed it

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::test {

class TcpTestClient {
public:
    explicit TcpTestClient(int port);
    ~TcpTestClient();
    TcpTestClient(const TcpTestClient&) = delete;
    TcpTestClient& operator=(const TcpTestClient&) = delete;

    static std::vector<unsigned char> framed(const std::vector<unsigned char>& packet);
    void send_bytes(const std::vector<unsigned char>& bytes);
    std::size_t offer_bytes(const std::vector<unsigned char>& bytes);
    void discard_received();
    void send(const std::string& address, const std::vector<protocol::OscArgument>& args = {});
    std::optional<protocol::DecodedMessage> receive(std::chrono::milliseconds timeout);
    std::optional<protocol::DecodedMessage> request(const std::string& address, const std::vector<protocol::OscArgument>& args,
                                                    const std::string& reply, std::chrono::milliseconds timeout = std::chrono::seconds(2));
    bool closed_by_server(std::chrono::milliseconds timeout);

private:
    std::optional<protocol::DecodedMessage> receive_until(std::chrono::steady_clock::time_point end);
    bool read_exactly(unsigned char* out, std::size_t n, std::chrono::steady_clock::time_point end);
    int fd_ = -1;
};

}  // namespace ameoto::test
