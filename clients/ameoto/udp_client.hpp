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

class UdpClient {
public:
    static std::unique_ptr<UdpClient> open(const Target& target, std::string& error);
    ~UdpClient();
    UdpClient(const UdpClient&) = delete;
    UdpClient& operator=(const UdpClient&) = delete;

    bool send(const std::vector<unsigned char>& bytes, std::string& error);
    Received receive(Deadline deadline);

private:
    explicit UdpClient(int fd) : fd_(fd) {}
    int fd_;
};

}  // namespace ameoto::client
