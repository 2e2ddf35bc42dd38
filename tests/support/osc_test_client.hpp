// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A UDP OSC client for tests: real datagrams over loopback, every wait bounded.
//
// Interface:
//   OscTestClient c(port);                                   // bound to an ephemeral local port
//   c.send("/rain/rate", {OscArgument::from_float(30)});
//   c.send_raw(bytes);                                       // anything, for malformed input
//   auto reply = c.receive(500ms);                           // next message, or nullopt
//   auto r = c.request("/status", {}, "/status.reply", 2s);  // send, then wait for that address
//                                                            // (request and wait_for wait 4 times as
//                                                            // long under the sanitizers: timing_scale.hpp)
//                                                            // (other replies are kept in c.others)

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::test {

class OscTestClient {
public:
    explicit OscTestClient(int server_port);
    ~OscTestClient();
    void send(const std::string& address, const std::vector<protocol::OscArgument>& args = {});
    void send_raw(const std::vector<unsigned char>& bytes);
    std::optional<protocol::DecodedMessage> receive(std::chrono::milliseconds timeout);
    std::optional<protocol::DecodedMessage> request(const std::string& address, const std::vector<protocol::OscArgument>& args,
                                                    const std::string& reply_address, std::chrono::milliseconds timeout);
    std::optional<protocol::DecodedMessage> wait_for(const std::string& reply_address, std::chrono::milliseconds timeout);
    std::vector<protocol::DecodedMessage> others;

private:
    int fd_ = -1;
    int port_;
};

}  // namespace ameoto::test
