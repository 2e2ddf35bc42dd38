// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod --block-trace: a daemon playing in real time writes its slow callbacks to the file, and a
// block forced to be slow (12 lattice drops spawned at one sample, several times the work a 64-frame period
// holds) is there, marked as our own work with the drops it spawned.

#include <doctest/doctest.h>
#include <signal.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;

namespace {
std::vector<std::string> fields(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string f; in >> f;) out.push_back(f);
    return out;
}
}  // namespace

TEST_CASE("--block-trace writes the slow callbacks, and a forced one is there as ours") {
    const std::string trace = ameoto::test::temp_path("slow-blocks.trace");
    {
        ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--block", "64", "--rain", "0",
                                       "--fixed-detail", "--block-trace", trace});
        CHECK(d.process().output().find("tracing callbacks over 50 % of the period to " + trace) != std::string::npos);
        ameoto::test::OscTestClient c(d.port());
        REQUIRE(c.request("/lod", {OscArgument::from_float(50.0f), OscArgument::from_int(64)}, "/done", 5s));
        // 12 drops of 5 mm in one immediate bundle: all applied at the first sample of one block.
        std::vector<std::vector<unsigned char>> drops;
        for (int k = 0; k < 12; ++k) {
            const double angle = 2.0 * M_PI * k / 12.0, radius = 0.1 + 0.25 * (k % 3) / 2.0;
            drops.push_back(ameoto::protocol::encode_message(
                "/drop", {OscArgument::from_float(5.0f), OscArgument::from_float(0.0f),
                          OscArgument::from_float(static_cast<float>(radius * std::cos(angle))),
                          OscArgument::from_float(static_cast<float>(radius * std::sin(angle)))}));
        }
        c.send_raw(ameoto::protocol::encode_bundle(ameoto::protocol::Timetag{0, 1}, drops));
        REQUIRE(c.request("/sync", {OscArgument::from_int(1)}, "/synced", 10s));
        std::this_thread::sleep_for(500ms);
        REQUIRE(d.process().stop(SIGTERM, 20s) == 0);
        CHECK(d.process().output().find("block trace: ") != std::string::npos);
    }
    std::ifstream in(trace);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    REQUIRE(lines.size() >= 4);
    CHECK(lines[0].rfind("# ameotod block trace 1", 0) == 0);
    const auto names = fields(lines[2]);
    REQUIRE(names.size() > 10);
    CHECK(names[0] == "time_s");
    auto column = [&](const std::string& name) {
        for (std::size_t i = 0; i < names.size(); ++i)
            if (names[i] == name) return i;
        FAIL("no column " << name);
        return std::size_t{0};
    };
    int forced = 0;
    for (std::size_t i = 3; i + 1 < lines.size(); ++i) {
        const auto row = fields(lines[i]);
        REQUIRE(row.size() == names.size());   // every block line is complete
        if (row[column("cause")] == "ours" && std::stoi(row[column("spawned")]) >= 10 &&
            std::stoi(row[column("commands")]) >= 12 && std::stod(row[column("cpu_pct")]) > 50.0)
            ++forced;
    }
    CHECK(forced == 1);
    CHECK(lines.back().rfind("# blocks ", 0) == 0);   // the summary, written at shutdown
}
