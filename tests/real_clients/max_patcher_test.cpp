// SPDX-License-Identifier: GPL-3.0-or-later
// clients/max/ameoto.maxpat. Max does not run on Linux, so this checks what can be checked here: the
// file is a well-formed patcher (JSON read by Python's json; boxes and patch lines consistent), it
// has [udpsend] to ameotod's default port and [udpreceive 7771], sends /reply/port 7771 on load, and every OSC address it sends is one
// the server's protocol table knows.

#include <doctest/doctest.h>

#include <sstream>
#include <string>

#include "protocol/address_table.hpp"
#include "tests/real_clients/real_programs.hpp"
#include "tests/support/child_process.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test;

TEST_CASE("Max: ameoto.maxpat is a well-formed patcher whose every address is in the protocol table") {
    const std::string python = "/usr/bin/python3";
    if (run_program({python, "-c", "import json"}, 10s).exit_code != 0) return skip_because_absent(python, "python3");
    const ProgramRun run = run_program({python, test_file("max/maxpat_messages.py"), client_path("max/ameoto.maxpat")}, 10s);
    INFO("maxpat_messages.py printed:\n" << run.out);
    REQUIRE(run.exit_code == 0);
    CHECK(run.out.find("object udpsend 127.0.0.1 7770\n") != std::string::npos);
    CHECK(run.out.find("object udpreceive 7771\n") != std::string::npos);
    // [udpsend] never listens: the patch asks for its replies on [udpreceive]'s port when it opens.
    CHECK(run.out.find("on load /reply/port 7771\n") != std::string::npos);
    std::istringstream lines(run.out);
    int addresses = 0;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("sends ", 0) != 0) continue;
        const std::string address = line.substr(6);
        CAPTURE(address);
        CHECK(ameoto::protocol::find_address(address) != nullptr);
        ++addresses;
    }
    CHECK(addresses >= 10);
}
