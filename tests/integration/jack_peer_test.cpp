// SPDX-License-Identifier: GPL-3.0-or-later
// tests/bench/jack_peer.cpp (the fixed-load JACK client that tests/bench/xrun-floor runs beside
// nothing else, to tell the machine's slow callbacks and xruns from ameotod's): it refuses bad
// arguments, says when no JACK server runs, and on a real jackd (dummy driver) prints its figures.

#include <doctest/doctest.h>

#include <cstdio>
#include <string>

#include "tests/support/child_process.hpp"
#include "tests/support/jack_server.hpp"

using namespace std::chrono_literals;

namespace {

const std::string peer = AMEOTO_JACK_PEER;
const ameoto::test::ChildOptions stderr_apart = [] {
    ameoto::test::ChildOptions o;
    o.separate_stderr = true;
    return o;
}();

}  // namespace

TEST_CASE("jack_peer refuses arguments out of range and says when no JACK server runs") {
    for (const auto& args : {std::vector<std::string>{}, {"0", "1", "10"}, {"5", "-1", "10"}, {"5", "1", "95"}, {"5", "1", "x"},
                             {"5", "1", "10", "more"}}) {
        std::vector<std::string> argv{peer};
        argv.insert(argv.end(), args.begin(), args.end());
        const auto run = ameoto::test::run_program(argv, 10s, {}, stderr_apart);
        CHECK(run.exit_code == 2);
        CHECK(run.err.find("usage: jack_peer SECONDS") != std::string::npos);
    }
    const auto alone = ameoto::test::run_program({peer, "1", "1", "10"}, 20s, {"JACK_DEFAULT_SERVER=ameoto-no-such-server"}, stderr_apart);
    CHECK(alone.exit_code == 1);
    CHECK(alone.err.find("is jackd running?") != std::string::npos);
}

TEST_CASE("jack_peer on a real jackd: a callback every period, with its CPU time and JACK's xruns counted") {
    ameoto::test::JackServer jack;
    // 3 s of 1 MB walked at 10 % of each 256-frame period.
    const auto run = ameoto::test::run_program({peer, "3", "1", "10"}, 30s, jack.env());
    INFO("jack_peer printed:\n" << run.out << run.err);
    REQUIRE(run.exit_code == 0);
    const std::size_t at = run.out.rfind("3 s: callbacks ");
    REQUIRE(at != std::string::npos);
    long callbacks = -1, over_50 = -1, over_100 = -1, xruns = -1;
    double mean = -1.0, largest = -1.0, wall_s = -1.0;
    REQUIRE(std::sscanf(run.out.c_str() + at,
                        "3 s: callbacks %ld mean_cpu_pct %lf max_cpu_pct %lf over_50 %ld over_100 %ld xruns %ld wall_s %lf", &callbacks,
                        &mean, &largest, &over_50, &over_100, &xruns, &wall_s) == 7);
    // The client was active for at least its 3 s (its main thread sleeps three times 1 s, and on a
    // busy machine, as in CI's sanitized run beside another suite, may oversleep): at most one
    // callback per 256-frame period of that wall time (187.5 a second at 48 kHz), and one more for a
    // period under way at activation. The dummy driver without real-time scheduling, on a busy
    // machine, may run fewer; a run with none would mean the client never ran.
    CHECK(wall_s >= 3.0);
    CHECK(callbacks > 0);
    CHECK(callbacks <= static_cast<long>(wall_s * 48000.0 / 256.0) + 2);
    CHECK(mean > 0.0);
    CHECK(largest >= mean);
    CHECK(over_100 <= over_50);
    CHECK(over_50 <= callbacks);
    CHECK(xruns >= 0);
}
