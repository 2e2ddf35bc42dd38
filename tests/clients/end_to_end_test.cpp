// SPDX-License-Identifier: GPL-3.0-or-later
// The real programs: ameotod on the null backend, driven by the ameoto binary as a user would.
#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>

#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/timing_scale.hpp"

using namespace std::chrono_literals;
using ameoto::test::ChildOptions;
using ameoto::test::DaemonProcess;
using ameoto::test::ProgramRun;
using ameoto::test::run_program;

namespace {

using ameoto::test::ameoto_bin;
const std::string& ameotod_bin = ameoto::test::ameotod;

// Children get the test's environment minus these, so a developer's shell settings cannot point
// the tests at another server.
const std::vector<std::string> ameoto_variables{"AMEOTO_HOST", "AMEOTO_PORT"};

// ameotod on the null backend, --port 0: it said where it listens (within 5 s) and that it runs.
DaemonProcess start_server() {
    ameoto::test::DaemonOptions o;
    o.listen_timeout = 30s;   // the scene takes seconds to build (5.6 s at load 12.6): as watch_test
    o.child.unset_env = ameoto_variables;
    return DaemonProcess({"--backend", "null", "--output", "-", "--realtime"}, {}, o);
}

// Every run is bounded: a hanging CLI fails the test instead of stalling the suite. stdout and
// stderr are kept apart.
ProgramRun run_ameoto(std::vector<std::string> words) {
    words.insert(words.begin(), ameoto_bin);
    ChildOptions o;
    o.unset_env = ameoto_variables;
    o.separate_stderr = true;
    return run_program(words, 5s, {}, o);
}

// A port on 127.0.0.1 that nothing listens on (just freed).
int closed_udp_port() {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    socklen_t size = sizeof a;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size) != 0)
        throw std::runtime_error(std::string("cannot find a free UDP port: ") + std::strerror(errno));
    close(fd);   // the kernel hands out ephemeral ports in turn, so this one stays free for a while
    return ntohs(a.sin_port);
}

void require_binaries() {
    // clients_tests does not depend on these targets (tests/CMakeLists.txt): build everything first.
    REQUIRE_MESSAGE(std::filesystem::exists(ameoto_bin), ameoto_bin << " is missing: run make in the build folder");
    REQUIRE_MESSAGE(std::filesystem::exists(ameotod_bin), ameotod_bin << " is missing: run make in the build folder");
}

// The number after "key": in ameoto status --json output; NaN when absent.
double json_number(const std::string& json, const std::string& key) {
    const std::string tag = "\"" + key + "\": ";
    const auto at = json.find(tag);
    if (at == std::string::npos) return std::nan("");
    return std::strtod(json.c_str() + at + tag.size(), nullptr);
}

std::string describe(const ProgramRun& r) {
    return "exit " + std::to_string(r.exit_code) + (r.timed_out ? " (timed out)" : "") + "\nstdout:\n" + r.out +
           "stderr:\n" + r.err;
}

}  // namespace

TEST_CASE("ameoto drives a real ameotod: send, /fail, status, sync, quit") {
    require_binaries();
    DaemonProcess server = start_server();
    CHECK(server.listening_line().starts_with("ameotod: listening on osc.udp://127.0.0.1:"));
    const std::string port = std::to_string(server.port());

    // Accepted: no reply comes, so send listens the whole default 0.5 s for a /fail, then exits 0.
    const ProgramRun rate = run_ameoto({"send", "--port", port, "/rain/rate", "30"});
    const auto rate_sent = std::chrono::steady_clock::now();
    INFO(describe(rate));
    CHECK(rate.exit_code == 0);
    CHECK(rate.out.empty());
    CHECK(rate.seconds >= 0.45);

    // Refused: the /fail names the range, and ends the wait at once (well before the 10 s asked for;
    // see the /sync below).
    const ProgramRun refused = run_ameoto({"send", "--port", port, "--wait", "10", "/rain/rate", "900"});
    INFO(describe(refused));
    CHECK(refused.exit_code == 1);
    CHECK(refused.out == "/fail \"/rain/rate\" \"argument 1 rate (mm/h): 900 is outside 0..500\"\n");
    CHECK(refused.seconds < 5.0);

    const ProgramRun early = run_ameoto({"status", "--port", port, "--json"});
    INFO(describe(early));
    REQUIRE(early.exit_code == 0);
    const double rate_early = json_number(early.out, "rain_rate_mm_per_h");

    // The rate ramps over 1 s of audio, applied before the reply above was made: once the audio clock
    // (seconds_rendered) has moved 1.05 s on, it is there. The audio clock, not the wall's: under the
    // sanitizers the null backend renders slower than real time.
    const double early_seconds = json_number(early.out, "seconds_rendered");
    REQUIRE(std::isfinite(early_seconds));
    std::this_thread::sleep_until(rate_sent + std::chrono::milliseconds(1200));
    ProgramRun later = run_ameoto({"status", "--port", port, "--json"});
    const auto give_up = std::chrono::steady_clock::now() + ameoto::test::scaled(std::chrono::seconds(20));
    while (later.exit_code == 0 && json_number(later.out, "seconds_rendered") < early_seconds + 1.05 &&
           std::chrono::steady_clock::now() < give_up) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        later = run_ameoto({"status", "--port", port, "--json"});
    }
    INFO(describe(later));
    REQUIRE(later.exit_code == 0);
    CHECK(json_number(later.out, "seconds_rendered") >= early_seconds + 1.05);
    CHECK(later.out.starts_with("{\"cpu_average_percent\": "));
    CHECK(later.out.ends_with("}\n"));
    CHECK(later.out.find("\"backend\": \"null\"") != std::string::npos);
    CHECK(json_number(later.out, "sample_rate_hz") == 48000.0);
    CHECK(json_number(later.out, "seconds_rendered") > 0.0);
    const double rate_later = json_number(later.out, "rain_rate_mm_per_h");
    CHECK(std::abs(rate_later - 30.0) <= std::abs(rate_early - 30.0));
    CHECK(rate_later == doctest::Approx(30.0).epsilon(0.01));

    const ProgramRun text = run_ameoto({"status", "--port", port});
    INFO(describe(text));
    CHECK(text.exit_code == 0);
    CHECK(text.out.find("\ncpu peak: ") != std::string::npos);
    CHECK(text.out.find("\nrain rate: 30 mm/h\n") != std::string::npos);
    CHECK(text.out.find("\nsample rate: 48000 Hz\n") != std::string::npos);
    CHECK(text.out.find("\nbackend: null\naudio clock against the wall: 0 ppm\n") != std::string::npos);
    CHECK(text.out.ends_with("\nfull scale: 133.98 dB SPL\n"));   // the harness's --level physical: 1.0 = 100 Pa

    // A known reply ends the wait as soon as it comes: well before the 10 s asked for. (Not a speed
    // bound: under the sanitizers, on a busy machine, the round trip with both programs' start-up
    // took 1.04 s.)
    const ProgramRun sync = run_ameoto({"send", "--port", port, "--wait", "10", "/sync", "7"});
    INFO(describe(sync));
    CHECK(sync.exit_code == 0);
    CHECK(sync.out == "/synced 7\n");
    CHECK(sync.seconds < 5.0);

    const ProgramRun drop = run_ameoto({"send", "--port", port, "--wait", "0", "/drop", "3", "0", "0.2", "0.1"});
    CHECK(drop.exit_code == 0);

    const ProgramRun quit = run_ameoto({"send", "--port", port, "--wait", "10", "/quit"});
    INFO(describe(quit));
    CHECK(quit.exit_code == 0);
    CHECK(quit.out == "/done \"/quit\"\n");
    CHECK(quit.seconds < 5.0);   // the /done ended the wait
    CHECK(server.process().wait(3s) == 0);
}

TEST_CASE("status with nothing listening fails quickly with a clear message") {
    require_binaries();
    const std::string port = std::to_string(closed_udp_port());
    const ProgramRun r = run_ameoto({"status", "--port", port});
    INFO(describe(r));
    CHECK(r.exit_code == 1);
    CHECK(r.out.empty());
    CHECK(r.err.find("no reply from 127.0.0.1:" + port) != std::string::npos);
    CHECK(r.err.find("is ameotod running?") != std::string::npos);
    CHECK(r.seconds < 1.0);

    const ProgramRun s = run_ameoto({"send", "--port", port, "/rain/rate", "30"});
    INFO(describe(s));
    CHECK(s.exit_code == 3);
    CHECK(s.err.find("nothing is listening on 127.0.0.1:" + port) != std::string::npos);
}

TEST_CASE("the dispatcher: help, version, unknown commands") {
    require_binaries();
    for (const auto& words : std::vector<std::vector<std::string>>{{"--help"}, {"help"}, {"-h"}}) {
        const ProgramRun r = run_ameoto(words);
        INFO(describe(r));
        CHECK(r.exit_code == 0);
        CHECK(r.out.starts_with("usage: ameoto COMMAND"));
        for (const char* needle : {"mm/h", "drop diameter mm", "m/s", "positions m", "ameoto send /rain/rate 30",
                                   "ameoto send /drop 3 0 0.2 0.1", "ameoto status"})
            CHECK_MESSAGE(r.out.find(needle) != std::string::npos, needle);
    }
    for (const auto& words : std::vector<std::vector<std::string>>{{"send", "--help"}, {"help", "send"}}) {
        const ProgramRun r = run_ameoto(words);
        CHECK(r.exit_code == 0);
        CHECK(r.out.starts_with("usage: ameoto send"));
        CHECK(r.out.find("/rain/rate rate") != std::string::npos);
    }
    const ProgramRun status_help = run_ameoto({"help", "status"});
    CHECK(status_help.exit_code == 0);
    CHECK(status_help.out.find("rain_rate_mm_per_h") != std::string::npos);

    const ProgramRun version = run_ameoto({"--version"});
    CHECK(version.exit_code == 0);
    CHECK(version.out.starts_with("ameoto "));

    const ProgramRun none = run_ameoto({});
    CHECK(none.exit_code == 2);
    CHECK(none.err.starts_with("usage: ameoto"));

    const ProgramRun unknown = run_ameoto({"play"});
    CHECK(unknown.exit_code == 2);
    CHECK(unknown.err == "ameoto: unknown command 'play' (see ameoto --help)\n");

    const ProgramRun missing = run_ameoto({"send"});
    CHECK(missing.exit_code == 2);
    CHECK(missing.err.starts_with("ameoto send: missing ADDRESS"));
}
