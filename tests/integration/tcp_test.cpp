// SPDX-License-Identifier: GPL-3.0-or-later
// OSC over TCP against the real daemon (--tcp-port): OSC 1.0 stream framing, replies on the same
// connection, the same validation as UDP, and bounds that keep one bad connection from harming others.

#include <doctest/doctest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/tcp_test_client.hpp"
#include "tests/support/osc_shorthand.hpp"

using namespace ameoto::test::osc_shorthand;

using namespace std::chrono_literals;
using ameoto::protocol::DecodedMessage;
using ameoto::protocol::OscArgument;
// ameotod ARGS --port 0 (DaemonOptions' start-up bound allows for a loaded machine).
using Daemon = ameoto::test::DaemonProcess;
using TcpClient = ameoto::test::TcpTestClient;

namespace {

// The TCP port from "ameotod: listening on osc.tcp://127.0.0.1:PORT/", which must be there.
int tcp_port(Daemon& d) {
    REQUIRE(d.tcp_port() > 0);
    return d.tcp_port();
}

}  // namespace

TEST_CASE("OSC over TCP: replies on the same connection, the same validation as UDP, bound to --bind") {
    Daemon d({"--backend", "null", "--output", "-", "--tcp-port", "0"});
    const int port = tcp_port(d);
    CHECK(d.process().output().find("listening on osc.tcp://127.0.0.1:") != std::string::npos);
    TcpClient c(port);
    const auto status = c.request("/status", {}, "/status.reply");
    REQUIRE(status);
    CHECK(status->types == "fffiiiiififfsfif");
    const auto synced = c.request("/sync", {i(42)}, "/synced");
    REQUIRE(synced);
    CHECK(synced->args[0].integer == 42);
    const auto fail = c.request("/rain/rate", {f(900)}, "/fail");
    REQUIRE(fail);
    CHECK(fail->args[0].text == "/rain/rate");
    CHECK(fail->args[1].text.find("outside 0..500") != std::string::npos);
    c.send("/rain/rate", {f(25)});
    const auto rate = c.request("/rain/rate", {}, "/rain/rate.reply");
    REQUIRE(rate);
    CHECK(rate->args[0].number == doctest::Approx(25));
    const auto version = c.request("/version", {}, "/version.reply");
    REQUIRE(version);
    CHECK(version->args[4].integer == port);

    // A packet split across writes, and two packets in one write: the stream is framed, not read in chunks.
    const auto a = TcpClient::framed(ameoto::protocol::encode_message("/sync", {i(1)}));
    const auto b = TcpClient::framed(ameoto::protocol::encode_message("/sync", {i(2)}));
    c.send_bytes({a.begin(), a.begin() + 3});
    std::this_thread::sleep_for(50ms);
    std::vector<unsigned char> rest(a.begin() + 3, a.end());
    rest.insert(rest.end(), b.begin(), b.end());
    c.send_bytes(rest);
    const auto one = c.receive(2s);
    const auto two = c.receive(2s);
    REQUIRE(one);
    REQUIRE(two);
    CHECK(one->args[0].integer == 1);
    CHECK(two->args[0].integer == 2);
    // UDP still serves alongside.
    ameoto::test::OscTestClient udp(d.port());
    CHECK(udp.request("/status", {}, "/status.reply", 2s));
}

TEST_CASE("a bad or lost TCP connection goes alone; at most 16 at once") {
    Daemon d({"--backend", "null", "--output", "-", "--tcp-port", "0"});
    const int port = tcp_port(d);
    TcpClient good(port);
    REQUIRE(good.request("/status", {}, "/status.reply"));

    // One daemon for all of these, in turn (each start costs seconds of CPU).
    {   // a packet over 64 KiB closes its connection
        TcpClient bad(port);
        bad.send_bytes({0x7f, 0xff, 0xff, 0xff});
        CHECK(bad.closed_by_server(2s));
    }
    {   // garbage inside a well-framed packet is a /fail, and the connection stays
        TcpClient bad(port);
        bad.send_bytes(TcpClient::framed({'/', 'x', 0, 0, 'n', 'o', 't', 0}));
        CHECK(bad.receive(2s)->address == "/fail");
        CHECK(bad.request("/status", {}, "/status.reply"));
    }
    {   // a client that vanishes mid-packet
        auto lost = std::make_unique<TcpClient>(port);
        lost->send_bytes({0, 0, 0, 64, '/', 's'});
        lost.reset();
    }
    {   // a subscriber that vanishes frees its place
        auto sub = std::make_unique<TcpClient>(port);
        REQUIRE(sub->request("/notify", {i(1)}, "/done"));
        REQUIRE(sub->receive(2s));   // a /meter or /status.reply: it is subscribed
        sub.reset();
        std::this_thread::sleep_for(200ms);
        // 16 others can now subscribe, so the lost one no longer counts.
        std::vector<std::unique_ptr<ameoto::test::OscTestClient>> others;
        for (int k = 0; k < 16; ++k) {
            others.push_back(std::make_unique<ameoto::test::OscTestClient>(d.port()));
            CHECK(others.back()->request("/notify", {i(1)}, "/done", 2s));
        }
    }
    std::this_thread::sleep_for(300ms);   // the server has seen the connections above close
    {   // the 17th connection is closed at once; one more fits when one leaves
        std::vector<std::unique_ptr<TcpClient>> many;
        for (int k = 0; k < 15; ++k) many.push_back(std::make_unique<TcpClient>(port));   // with `good`: 16
        for (auto& m : many) REQUIRE(m->request("/sync", {i(3)}, "/synced"));
        TcpClient extra(port);
        CHECK(extra.closed_by_server(2s));
        many.pop_back();
        std::this_thread::sleep_for(200ms);
        TcpClient again(port);
        CHECK(again.request("/sync", {i(4)}, "/synced"));
    }
    // Whatever happened to the others, this connection and UDP still work.
    CHECK(good.request("/sync", {i(9)}, "/synced"));
    ameoto::test::OscTestClient udp(d.port());
    CHECK(udp.request("/status", {}, "/status.reply", 2s));
    CHECK(d.process().running());
}

TEST_CASE("--tcp-port on a port already in use fails at start with the reason") {
    Daemon first({"--backend", "null", "--output", "-", "--tcp-port", "0"});
    const int taken = tcp_port(first);
    ameoto::test::ChildProcess second({AMEOTO_BIN_DIR "/ameotod", "--backend", "null", "--output", "-", "--port", "0", "--tcp-port",
                                       std::to_string(taken)});
    CHECK(second.wait(30s) == 1);   // it builds its scene before it binds: seconds on a loaded machine
    CHECK(second.output().find("cannot listen on TCP 127.0.0.1:" + std::to_string(taken)) != std::string::npos);
}
