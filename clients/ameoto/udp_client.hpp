// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One UDP socket connected to the server: send datagrams, receive its replies with a deadline.
//
// Interface:
//   std::string error;
//   auto client = UdpClient::open(target, error);       // nullptr + error: unknown host, no socket
//   if (!client->send(bytes, error)) ...                  // not sent
//   Received r = client->receive(deadline);               // a datagram, or why there is none
//
// Why connect(): the kernel then delivers only datagrams from the server's address and port, and
// reports an ICMP "port unreachable" as ECONNREFUSED, so "nothing listens there" is known at
// once instead of after the whole timeout (on this machine always; across a network when the
// host answers with ICMP at all).
// Why IPv4 first: ameotod binds 127.0.0.1 by default, and "localhost" often resolves to ::1 first.
// Every receive has a deadline: the CLI must never hang.
//
// Over TCP (`UdpClient::open(target, error, Transport::tcp)`, for `ameoto send --tcp`): the same
// interface on a connected stream, OSC 1.0 framing (each packet preceded by its size as a big-endian
// int32): send() frames, receive() returns one whole packet; a server that closes the connection is
// reported as refused.

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "clients/ameoto/target.hpp"

namespace ameoto::client {

using Deadline = std::chrono::steady_clock::time_point;

struct Received {
    enum class Outcome { datagram, timeout, refused, error };
    Outcome outcome = Outcome::timeout;
    std::vector<unsigned char> bytes;   // for datagram
    std::string error;                  // for error
};

enum class Transport { udp, tcp };

class UdpClient {
public:
    static std::unique_ptr<UdpClient> open(const Target& target, std::string& error, Transport transport = Transport::udp);
    ~UdpClient();
    UdpClient(const UdpClient&) = delete;
    UdpClient& operator=(const UdpClient&) = delete;

    bool send(const std::vector<unsigned char>& bytes, std::string& error);
    Received receive(Deadline deadline);

private:
    UdpClient(int fd, bool stream) : fd_(fd), stream_(stream) {}
    enum class Wait { ready, again, failed };
    Wait wait_readable(Deadline deadline, Received& r) const;
    Received receive_packet(Deadline deadline);   // TCP: the next whole packet from the stream
    int fd_;
    bool stream_;
    std::vector<unsigned char> stream_bytes_;   // TCP: received, not yet a whole packet
};

}  // namespace ameoto::client
