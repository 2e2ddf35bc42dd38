// SPDX-License-Identifier: GPL-3.0-or-later
// /reply/port against the real daemon over real UDP: a client sends from one socket (as Max's [udpsend]
// does, from a port it never reads) and hears every reply on a second socket bound to the port it named
// (as Max's [udpreceive] does); nothing comes back to the sending socket. Port 0 restores the sender's
// own port, bad values are refused on the original port, /notify subscribers follow the redirect, and a
// TCP client is refused (its replies always come back on its connection). A reply sent to the server is
// never answered, so a redirect aimed at a server cannot start an endless exchange.

#include <doctest/doctest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/tcp_test_client.hpp"
#include "tests/support/osc_shorthand.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace std::chrono_literals;
using ameoto::protocol::DecodedMessage;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;

namespace {

// ameotod ARGS --port 0 (DaemonOptions' start-up bound allows for a loaded machine).
using Daemon = ameoto::test::DaemonProcess;

// A socket that only listens, like Max's [udpreceive PORT]: bound to a loopback port of its own.
class Listener {
public:
    Listener() {
        fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        sockaddr_in local{};
        local.sin_family = AF_INET;
        local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t size = sizeof local;
        if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0 ||
            getsockname(fd_, reinterpret_cast<sockaddr*>(&local), &size) != 0)
            throw std::runtime_error("listener socket");
        port_ = ntohs(local.sin_port);
    }
    ~Listener() { close(fd_); }
    int port() const { return port_; }
    std::optional<DecodedMessage> receive(std::chrono::milliseconds timeout) {
        pollfd p{fd_, POLLIN, 0};
        if (poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
        unsigned char buffer[65536];
        const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
        if (n <= 0) return std::nullopt;
        auto packet = ameoto::protocol::decode_packet(buffer, static_cast<std::size_t>(n));
        if (!packet.error.empty() || packet.messages.empty()) return std::nullopt;
        return packet.messages.front();
    }
    // The next message with this address (others are skipped: /meter, periodic /status.reply).
    std::optional<DecodedMessage> wait_for(const std::string& address, std::chrono::milliseconds timeout) {
        const auto end = std::chrono::steady_clock::now() + timeout;
        for (;;) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
            if (left.count() <= 0) return std::nullopt;
            auto m = receive(left);
            if (!m) return std::nullopt;
            if (m->address == address) return m;
        }
    }

private:
    int fd_ = -1;
    int port_ = 0;
};

// Everything that reaches the sending socket within `span` (it should be nothing while redirected).
std::vector<std::string> arrivals(OscTestClient& c, std::chrono::milliseconds span) {
    std::vector<std::string> got;
    for (const auto& m : c.others) got.push_back(m.address);
    c.others.clear();
    const auto end = std::chrono::steady_clock::now() + span;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
        if (left.count() <= 0) break;
        if (auto m = c.receive(left)) got.push_back(m->address);
    }
    return got;
}

}  // namespace

TEST_CASE("after /reply/port P every reply to the sender goes to P at its address; /reply/port 0 restores its own port") {
    Daemon d({"--backend", "null", "--output", "-", "--rain", "3"});
    OscTestClient sender(d.port());
    Listener receiver;

    sender.send("/reply/port", {i(receiver.port())});
    const auto done = receiver.wait_for("/done", 2s);   // the /done already takes the new way
    REQUIRE_MESSAGE(done, "no /done /reply/port on the named port");
    CHECK(done->args[0].text == "/reply/port");

    sender.send("/status");
    const auto status = receiver.wait_for("/status.reply", 2s);
    REQUIRE(status);
    CHECK(status->types == "fffiiiiififfsfif");

    sender.send("/rain/rate", {f(12)});
    sender.send("/rain/rate");   // its query, answered from the applied state
    const auto rate = receiver.wait_for("/rain/rate.reply", 2s);
    REQUIRE(rate);
    CHECK(rate->args[0].number == doctest::Approx(12.0));

    sender.send("/reply/port");   // the query of /reply/port itself
    const auto port = receiver.wait_for("/reply/port.reply", 2s);
    REQUIRE(port);
    REQUIRE(port->types == "i");
    CHECK(port->args[0].integer == receiver.port());

    sender.send("/sync", {i(42)});   // answered from the audio thread's event, through the client table
    const auto synced = receiver.wait_for("/synced", 2s);
    REQUIRE(synced);
    CHECK(synced->args[0].integer == 42);

    sender.send("/rain/rate", {f(900)});   // valid /reply/port, then a refused value: the /fail follows too
    const auto fail = receiver.wait_for("/fail", 2s);
    REQUIRE(fail);
    CHECK(fail->args[0].text == "/rain/rate");

    CHECK(arrivals(sender, 300ms).empty());   // nothing came back to the port the client sends from

    // Port 0: replies go back to where the sender sends from, starting with this /done.
    const auto restored = sender.request("/reply/port", {i(0)}, "/done", 2s);
    REQUIRE_MESSAGE(restored, "no /done on the sender's own port after /reply/port 0");
    CHECK(restored->args[0].text == "/reply/port");
    CHECK(sender.request("/reply/port", {}, "/reply/port.reply", 2s)->args[0].integer == 0);
    REQUIRE(sender.request("/status", {}, "/status.reply", 2s));
    CHECK_FALSE(receiver.receive(300ms));   // and nothing on the listener any more
}

TEST_CASE("/reply/port refuses bad values with /fail on the sender's own port and keeps the redirect it had") {
    Daemon d({"--backend", "null", "--output", "-", "--rain", "3"});
    OscTestClient sender(d.port());
    for (const auto& bad : std::vector<std::vector<OscArgument>>{{i(65536)}, {i(-1)}, {f(7771.5)}, {OscArgument::from_string("7771")}, {i(7771), i(1)}}) {
        const auto fail = sender.request("/reply/port", bad, "/fail", 2s);
        REQUIRE_MESSAGE(fail, "no /fail on the sender's port");
        CHECK(fail->args[0].text == "/reply/port");
        CHECK_FALSE(fail->args[1].text.empty());
        CHECK(sender.request("/reply/port", {}, "/reply/port.reply", 2s)->args[0].integer == 0);   // unchanged
    }
    CHECK(sender.request("/reply/port", {i(65536)}, "/fail", 2s)->args[1].text.find("outside 0..65535") != std::string::npos);

    // A redirect in place stays through a refused change; the /fail goes where replies go now.
    Listener receiver;
    sender.send("/reply/port", {i(receiver.port())});
    REQUIRE(receiver.wait_for("/done", 2s));
    sender.send("/reply/port", {i(70000)});
    const auto fail = receiver.wait_for("/fail", 2s);
    REQUIRE(fail);
    CHECK(fail->args[0].text == "/reply/port");
    sender.send("/reply/port");
    CHECK(receiver.wait_for("/reply/port.reply", 2s)->args[0].integer == receiver.port());
}

TEST_CASE("a /notify subscriber that redirected gets its periodic /status.reply and /meter on the named port") {
    Daemon d({"--backend", "null", "--output", "-", "--rain", "30"});
    OscTestClient sender(d.port());
    Listener receiver;
    sender.send("/notify", {i(1)});   // subscribed first, redirected after: the subscription follows
    REQUIRE(sender.wait_for("/done", 2s));
    sender.send("/reply/port", {i(receiver.port())});
    REQUIRE(receiver.wait_for("/done", 2s));
    receiver.receive(0ms);
    // One periodic /status.reply a second and /meter ten times a second (notify_test checks the rates).
    CHECK(receiver.wait_for("/meter", 3s));
    CHECK(receiver.wait_for("/status.reply", 3s));
    const auto leaked = arrivals(sender, 1200ms);
    CHECK_MESSAGE(std::none_of(leaked.begin(), leaked.end(), [](const std::string& a) { return a == "/meter" || a == "/status.reply"; }),
                  "a notification reached the sending port");
}

TEST_CASE("a TCP client gets /fail for /reply/port: its replies always come back on its connection") {
    Daemon d({"--backend", "null", "--output", "-", "--tcp-port", "0"});
    REQUIRE(d.tcp_port() > 0);
    ameoto::test::TcpTestClient c(d.tcp_port());
    c.send("/reply/port", {i(7771)});
    const auto reply = c.receive(2s);   // the first packet back on the connection, whole and well formed
    REQUIRE_MESSAGE(reply, "no reply over TCP");
    REQUIRE(reply->args.size() == 2);
    CHECK(reply->address == "/fail");
    CHECK(reply->args[0].text == "/reply/port");
    CHECK(reply->args[1].text.find("TCP") != std::string::npos);
}

TEST_CASE("a reply sent to the server is never answered, so a redirect aimed at a server's own port cannot loop") {
    Daemon d({"--backend", "null", "--output", "-"});
    OscTestClient client(d.port());
    // Each of the server's replies, sent to it as a request: no /fail (a /fail to a server that answers
    // /fail with /fail would go on for ever); an unknown address still gets its /fail.
    for (const char* address : {"/done", "/fail", "/synced", "/notice", "/meter", "/status.reply", "/rain/rate.reply", "/reply/port.reply"})
        client.send(address, {OscArgument::from_string("/x")});
    const auto unknown = client.request("/no/such/address", {}, "/fail", 2s);
    REQUIRE(unknown);
    CHECK(unknown->args[0].text == "/no/such/address");
    CHECK(client.others.empty());

    // Replies aimed at the server itself: its /done comes back to it and is dropped; it keeps serving,
    // and the client can undo the redirect (its /done then comes back to the client).
    client.send("/reply/port", {i(d.port())});
    client.send("/status");
    OscTestClient other(d.port());
    REQUIRE(other.request("/status", {}, "/status.reply", 2s));
    const auto restored = client.request("/reply/port", {i(0)}, "/done", 2s);
    REQUIRE(restored);
    CHECK(restored->args[0].text == "/reply/port");
    CHECK(client.others.empty());   // nothing of the server talking to itself reached the client
}
