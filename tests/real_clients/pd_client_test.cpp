// SPDX-License-Identifier: GPL-3.0-or-later
// The shipped Pure Data abstraction clients/pd/ameoto.pd, run by the real pd (puredata-core)
// against the real ameotod and, to see every message it sends, against oscdump.

#include <doctest/doctest.h>

#include <csignal>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>

#include "protocol/address_table.hpp"
#include "tests/real_clients/free_udp_port.hpp"
#include "tests/real_clients/real_programs.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/sanitizer_bounds.hpp"

using namespace std::chrono_literals;
using namespace ameoto::test;

namespace {

ProgramRun run_pd_patch(const std::string& pd, const std::string& patch, int port) {
    // Realtime scheduling of messages (not -batch: the patch waits for replies on a real clock).
    return run_program({pd, "-nogui", "-nosound", "-nomidi", "-noprefs", "-stderr", "-path", client_path("pd"), "-open",
                        test_file(patch), "-send", "ameoto-test " + std::to_string(port)},
                       15s);
}

}  // namespace

TEST_CASE("Pd: [ameoto] sets the rain rate, sends drops, gets /fail, /synced and /status.reply") {
    const auto pd = find_program("pd");
    if (!pd) return skip_because_absent("pd", "puredata-core");
    DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0"}, {}, DaemonOptions::patient());
    const ProgramRun run = run_pd_patch(*pd, "pd/ameoto_client_test.pd", d.port());
    INFO("pd printed:\n" << run.out);
    REQUIRE(run.exit_code == 0);
    CHECK(run.out.find("timeout") == std::string::npos);
    // rate 900 is outside 0..500 mm/h: the reason reaches Pd's /fail outlet (spaces escaped by [print]).
    CHECK(run.out.find("fail: /rain/rate argument\\ 1\\ rate\\ (mm/h):\\ 900\\ is\\ outside\\ 0..500") != std::string::npos);
    CHECK(run.out.find("reply: synced 5") != std::string::npos);

    const auto status = name_value_lines(run.out, "status: ");
    REQUIRE(status.size() == 16);
    CHECK(status.at("backend") == "null");
    CHECK(std::stod(status.at("full_scale_db_spl")) == doctest::Approx(133.98).epsilon(1e-4));   // --level physical
    CHECK(status.at("clipped_samples") == "0");
    CHECK(status.at("sample_rate_hz") == "48000");
    CHECK(status.at("block_size_frames") == "256");
    CHECK(status.at("late_bundles") == "0");
    // The two drops the patch sent are lattice drops, alive for about half a second after /synced
    // (when the callback has time for them: under the sanitizers the governor sheds them to cheaper tiers).
    AMEOTO_CHECK_UNLESS_SANITIZED(std::stoi(status.at("active_drops_full")) >= 2);
    // The rate ramps from 0 towards 12 mm/h over 1 s: Pd asked within that second.
    const double reported_rate = std::stod(status.at("rain_rate_mm_per_h"));
    CHECK(reported_rate >= 0.0);
    CHECK(reported_rate <= 12.0);
    // seconds_rendered: the audio clock in seconds, a float Pd reads as it is.
    const double pd_seconds = std::stod(status.at("seconds_rendered"));
    CHECK(pd_seconds > 0.0);

    // The server's own view: the rate Pd set (and not the refused 900), once ramped.
    OscTestClient client(d.port());
    CHECK(settled_rain_rate(client) == doctest::Approx(12.0).epsilon(1e-6));
    const auto now = client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(now);
    CHECK(pd_seconds < now->args[10].number);
}

TEST_CASE("Pd: every [ameoto] command sends its documented address and arguments (oscdump)") {
    const auto pd = find_program("pd");
    const auto oscdump = find_program("oscdump");
    if (!pd) return skip_because_absent("pd", "puredata-core");
    if (!oscdump) return skip_because_absent("oscdump", "liblo-tools");
    const int port = free_udp_port();
    ChildProcess dump({*oscdump, "-L", std::to_string(port)});
    std::this_thread::sleep_for(300ms);   // oscdump binds its port before pd (slower to start) sends
    const ProgramRun run = run_pd_patch(*pd, "pd/ameoto_commands_test.pd", port);
    REQUIRE(run.exit_code == 0);
    std::this_thread::sleep_for(200ms);
    dump.stop(SIGTERM, 2s);
    const std::string& seen = dump.output();
    INFO("pd printed:\n" << run.out << "\noscdump printed:\n" << seen);
    // oscdump prints "TIMETAG ADDRESS TYPES ARGS"; what follows the timetag must be exactly these.
    const char* expected[] = {
        "/rain/rate f 10.000000",
        "/rain/wind fff 6.000000 90.000000 0.300000",
        "/rain/dsd sff \"gamma\" 2.000000 3.000000",
        "/drop ffff 3.000000 0.000000 0.200000 0.000000",
        "/drop ffffs 3.000000 0.000000 0.200000 0.000000 \"umbrella\"",
        "/material/liquid s \"milk\"",
        "/material/liquid sfff \"syrup\" 1300.000000 0.070000 5.000000",
        "/material/surface ss \"umbrella\" \"vinyl\"",
        "/scene/load s \"street\"",
        "/scene/save s \"mine\"",
        "/listener ffff 1.000000 0.500000 1.600000 30.000000",
        "/lod ff 50.000000 16.000000",
        "/gain f -6.000000",
        "/loudness f -18.000000",
        "/loudness ",
        "/listener/orientation fff 90.000000 -10.000000 5.000000",
        "/status ",
        "/sync f 3.000000",
        "/notify f 1.000000",
        "/version ",
        "/surface/add sssfffff \"roof\" \"plate\" \"tin\" 1.000000 0.600000 0.000000 1.000000 3.000000",
        "/surface/set sssfffff \"roof\" \"plate\" \"glass\" 1.000000 0.600000 0.000000 1.000000 3.000000",
        "/surface/remove s \"roof\"",
        "/rain/rate f 5.000000",
        "/rain/rate ",
        "/quit ",
    };
    check_oscdump_messages(seen, expected);   // and every address is in the server's table
}

TEST_CASE("Pd: the help patch opens with [ameoto] and every object created, without an error") {
    const auto pd = find_program("pd");
    if (!pd) return skip_because_absent("pd", "puredata-core");
    // -send "pd quit" runs once the patch is loaded (its [loadbang]s included).
    const ProgramRun run = run_program({*pd, "-nogui", "-nosound", "-nomidi", "-noprefs", "-stderr", "-path", client_path("pd"),
                                        "-open", client_path("pd/ameoto-help.pd"), "-send", "pd quit"},
                                       15s);
    INFO("pd printed:\n" << run.out);
    CHECK(run.exit_code == 0);
    // Pd reports an object it cannot create ("... couldn't create") and a stray message ("error: ...").
    CHECK(run.out.find("couldn't create") == std::string::npos);
    CHECK(run.out.find("error") == std::string::npos);
}
