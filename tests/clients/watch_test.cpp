// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto watch` against a real ameotod, as a user runs it: updates as lines on a pipe, --count,
// Ctrl-C unsubscribes, and a server that is not there.
#include <doctest/doctest.h>
#include <signal.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/program_paths.hpp"

using namespace std::chrono_literals;
using ameoto::test::ChildOptions;
using ameoto::test::ChildProcess;
using ameoto::test::DaemonProcess;

namespace {

using ameoto::test::ameoto_bin;
const std::vector<std::string> ameoto_variables{"AMEOTO_HOST", "AMEOTO_PORT"};

DaemonProcess start_server() {
    ameoto::test::DaemonOptions o;
    o.listen_timeout = 30s;   // the scene takes seconds to build on a loaded machine
    o.child.unset_env = ameoto_variables;
    return DaemonProcess({"--backend", "null", "--output", "-", "--rain", "20"}, {}, o);
}

ChildOptions child_options() {
    ChildOptions o;
    o.unset_env = ameoto_variables;
    o.separate_stderr = true;
    return o;
}

long count_lines_starting(const std::string& text, const std::string& start) {
    long n = 0;
    for (std::size_t at = 0; at < text.size();) {
        const auto end = text.find('\n', at);
        if (text.compare(at, start.size(), start) == 0) ++n;
        if (end == std::string::npos) break;
        at = end + 1;
    }
    return n;
}

}  // namespace

TEST_CASE("ameoto watch on a pipe: one line per update, --count ends it") {
    DaemonProcess server = start_server();
    const auto r = ameoto::test::run_program({ameoto_bin, "watch", "--port", std::to_string(server.port()), "--count", "15"}, 10s, {},
                                             child_options());
    INFO("stdout:\n" << r.out << "stderr:\n" << r.err);
    CHECK(r.exit_code == 0);
    const long meters = count_lines_starting(r.out, "meter t=");
    const long statuses = count_lines_starting(r.out, "status cpu=");
    CHECK(meters + statuses == 15);
    CHECK(meters >= 10);   // ten a second against one status a second
    CHECK(statuses >= 1);
    CHECK(r.out.find(" dBFS peak/rms M=") != std::string::npos);   // then the loudness: momentary, short-term, true peak
    CHECK(r.out.find(" LUFS TP=") != std::string::npos);
    CHECK(r.out.find(" dBTP\n") != std::string::npos);
    CHECK(r.out.find("backend=null") != std::string::npos);
    CHECK(r.out.find("\x1b[") == std::string::npos);   // no terminal codes in a pipe
}

TEST_CASE("Ctrl-C quits ameoto watch cleanly and frees its subscription") {
    DaemonProcess server = start_server();
    // 15 other subscribers: with watch, the server's 16 places are full.
    std::vector<std::unique_ptr<ameoto::test::OscTestClient>> others;
    for (int k = 0; k < 15; ++k) {
        others.push_back(std::make_unique<ameoto::test::OscTestClient>(server.port()));
        REQUIRE(others.back()->request("/notify", {ameoto::protocol::OscArgument::from_int(1)}, "/done", 2s));
    }
    ChildProcess watch({ameoto_bin, "watch", "--port", std::to_string(server.port())}, {}, child_options());
    REQUIRE(watch.wait_for_line("meter t=", 5s));
    ameoto::test::OscTestClient probe(server.port());
    CHECK(probe.request("/notify", {ameoto::protocol::OscArgument::from_int(1)}, "/fail", 2s));   // full while watch runs
    watch.signal(SIGINT);
    CHECK(watch.wait(3s) == 0);
    CHECK(probe.request("/notify", {ameoto::protocol::OscArgument::from_int(1)}, "/done", 2s));   // watch said /notify 0
}

TEST_CASE("ameoto watch with no server says so within about 2 s") {
    ChildOptions o = child_options();
    // Port 9 (discard) on loopback: nothing of ours listens there.
    const auto r = ameoto::test::run_program({ameoto_bin, "watch", "--port", "9"}, 10s, {}, o);
    INFO("stderr: " << r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("is ameotod running?") != std::string::npos);
    CHECK(r.seconds < 4.0);   // at once when the port refuses (ICMP), else after the 2 s wait
}

TEST_CASE("ameoto watch refuses bad options before sending anything") {
    for (const auto& words : std::vector<std::vector<std::string>>{{"--count", "0"}, {"--count", "2.5"}, {"--frobnicate"}, {"extra"}}) {
        std::vector<std::string> argv{ameoto_bin, "watch", "--port", "9"};
        argv.insert(argv.end(), words.begin(), words.end());
        const auto r = ameoto::test::run_program(argv, 5s, {}, child_options());
        INFO(words[0] << ": " << r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("ameoto watch: ") != std::string::npos);
    }
}
