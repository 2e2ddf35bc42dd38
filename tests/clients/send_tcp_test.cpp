// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto send --tcp` against a real ameotod started with --tcp-port: the same replies as over UDP.
#include <doctest/doctest.h>

#include <string>

#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/program_paths.hpp"

using namespace std::chrono_literals;

namespace {

using ameoto::test::ameoto_bin;

ameoto::test::ProgramRun send(const std::vector<std::string>& words) {
    std::vector<std::string> argv{ameoto_bin, "send"};
    argv.insert(argv.end(), words.begin(), words.end());
    ameoto::test::ChildOptions o;
    o.unset_env = {"AMEOTO_HOST", "AMEOTO_PORT"};
    o.separate_stderr = true;
    return ameoto::test::run_program(argv, 10s, {}, o);
}

}  // namespace

TEST_CASE("ameoto send --tcp: replies and refusals come back on the connection") {
    ameoto::test::DaemonOptions o;
    o.listen_timeout = 30s;
    ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--tcp-port", "0"}, {}, o);
    REQUIRE(d.tcp_port() > 0);
    const std::string port = std::to_string(d.tcp_port());

    auto r = send({"--port", port, "--tcp", "/sync", "5"});
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK(r.out == "/synced 5\n");
    r = send({"--port", port, "--tcp", "/rain/rate", "900"});
    CHECK(r.exit_code == 1);
    CHECK(r.out.starts_with("/fail \"/rain/rate\""));
    r = send({"--port", port, "--tcp", "/version"});
    CHECK(r.exit_code == 0);
    CHECK(r.out.starts_with("/version.reply \"ameotod\""));
    CHECK(r.out.ends_with(" " + port + "\n"));   // the TCP port it was reached on
    // The UDP port is not a TCP port: nothing accepts there.
    r = send({"--port", std::to_string(d.port()), "--tcp", "/sync", "1"});
    CHECK(r.exit_code == 3);
    CHECK(r.err.find("--tcp-port") != std::string::npos);
}
