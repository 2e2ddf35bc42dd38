// SPDX-License-Identifier: GPL-3.0-or-later
// oscsend (liblo-tools), the documented way to poke the server from a shell, against the real
// ameotod; the server's own /status says what changed. (oscdump, the other half of liblo-tools,
// is the receiver in pd_client_test.cpp: a sender's replies go to its own port, which oscsend
// closes at once.)

#include <doctest/doctest.h>

#include <string>

#include "tests/real_clients/real_programs.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test;
using ameoto::protocol::OscArgument;

TEST_CASE("oscsend: the examples of docs/PROTOCOL.md change the running server; a refused value changes nothing") {
    const auto oscsend = find_program("oscsend");
    if (!oscsend) return skip_because_absent("oscsend", "liblo-tools");
    DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0"}, {}, DaemonOptions::patient());
    const std::string port = std::to_string(d.port());
    OscTestClient client(d.port());

    REQUIRE(run_program({*oscsend, "localhost", port, "/drop", "ffff", "4", "0", "0.2", "0.1"}, 5s).exit_code == 0);
    REQUIRE(client.request("/sync", {OscArgument::from_int(1)}, "/synced", 2s));
    const auto after_drop = client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(after_drop);
    CHECK(after_drop->args[3].integer == 1);   // one lattice drop, and no rain to add others

    REQUIRE(run_program({*oscsend, "localhost", port, "/rain/rate", "f", "30"}, 5s).exit_code == 0);
    REQUIRE(run_program({*oscsend, "localhost", port, "/rain/rate", "f", "900"}, 5s).exit_code == 0);
    REQUIRE(client.request("/sync", {OscArgument::from_int(2)}, "/synced", 2s));
    CHECK(settled_rain_rate(client) == doctest::Approx(30.0).epsilon(1e-6));
}
