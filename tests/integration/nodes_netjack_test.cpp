// SPDX-License-Identifier: GPL-3.0-or-later
// Nodes over netjack2 on loopback (issue 23; recipe: ../shared/design/netjack2.md): a master jackd (dummy
// driver) with the netmanager on 127.0.0.1 (never multicast), two slave servers (`jackd -d net -a
// 127.0.0.1`), one ameotod on each playing half of the street; node 1 conducts node 2 (--peers). Each
// node's audio arrives on the master as nodeK:from_slave_N. Both start dry (--rain 0); one /rain/rate
// sent to node 1 only must start the rain on both at the same frame: the master's recording of the two
// nodes summed (JACK adds two ports feeding one input) then equals an offline render of the whole scene
// whose rain starts at one frame. Starting the rain at another frame only shifts that render (the rain
// draws nothing while it is 0: checked by rendering the change at 0.5 s and 1.0 s, identical but for
// 24 000 frames of shift), so the recording is aligned on its first sound; had node 2 started its rain
// even one frame off node 1, half the sum would be shifted against the other half. (The conductor puts
// the change on one of its block starts and sends it with /nodes/block; node 2 puts it on its own block
// start nearest that time: the two slaves' clocks place a cycle about 9 us apart, and when each node
// rounded the time to its own nearest sample, one take agreed for only 158 frames.)
// Not bit for bit: the two groups of surfaces are added in another order than in the whole (bound: 8
// float epsilons of the peak, as tests/integration/nodes_jack_test.cpp).

#include <doctest/doctest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <thread>

#include "protocol/osc_codec.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/jack_server.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/timing_scale.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;

namespace {

constexpr const char* street_split_dry =
    "ameoto-scene 3\n"
    "name street-split\n"
    "rain rate=0\n"
    "surface umbrella kind=umbrella material=nylon size=1 z=1.9\n"
    "surface car kind=plate material=car-roof size=1.2x1 x=2.5 y=-1.5 z=1.4 node=2\n"
    "surface window kind=plate material=glass size=0.8x0.6 x=-2 y=2 z=1 node=2\n"
    "surface puddle kind=water material=puddle size=1x0.8 x=1 y=1 z=0\n";

int free_udp_port() {
    const int s = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t n = sizeof a;
    getsockname(s, reinterpret_cast<sockaddr*>(&a), &n);
    close(s);
    return ntohs(a.sin_port);
}

// Lines in a JACK server's log since `from` that say a cycle went wrong: a client that did not finish
// (JackEngine::XRun), a process error, netjack2's missing or lost packets. A slave can lose a cycle that no
// client sees as an xrun (a late packet on the master), and it shifts that node's audio on the master
// against the other's for good: ameotod's own xrun count does not see it.
int trouble_lines(const std::string& log, std::size_t from) {
    int n = 0;
    for (std::size_t at = from; at < log.size();) {
        const std::size_t end = std::min(log.find('\n', at), log.size());
        const std::string line = log.substr(at, end - at);
        for (const char* word : {"XRun", "error", "missing", "lost", "too slow"})
            if (line.find(word) != std::string::npos) {
                ++n;
                break;
            }
        at = end + 1;
    }
    return n;
}

bool lsp_has(const std::vector<std::string>& env, const std::string& port) {
    return ameoto::test::run_program({"jack_lsp"}, 10s, env).out.find(port + "\n") != std::string::npos;
}

}  // namespace

TEST_CASE("nodes over netjack2 on loopback: both nodes' audio on the master; one conducted /rain/rate starts both at the same frame") {
    if (ameoto::test::stop_here_if_sanitized("netjack2's slaves and the dummy driver wait for clients slower than real time")) return;
    ameoto::test::TempDir dir("ameoto-nodes-netjack");
    const std::string scene = (dir.path() / "street-split-dry.scene").string();
    std::ofstream(scene) << street_split_dry;

    // The whole scene offline, dry, its rain started at 0.5 s (the same seed).
    const std::string score = (dir.path() / "rain.txt").string();
    const std::string whole_path = (dir.path() / "whole.wav").string();
    std::ofstream(score) << "0.5 /rain/rate 10\n";
    const auto render = ameoto::test::run_program({ameoto::test::ameoto_bin, "render", "score", score, "-o", whole_path, "--scene", scene, "--rain",
                                                   "0", "--seconds", "3", "--seed", "3", "--quiet"},
                                                  ameoto::test::scaled(60s));
    REQUIRE_MESSAGE(render.exit_code == 0, render.err);
    const auto whole = ameoto::test::read_wav(whole_path);
    REQUIRE(whole.ok);
    const long long whole_onset = whole.first_nonzero_frame();
    REQUIRE(whole_onset >= 24000);

    ameoto::test::JackServer master(true);
    const int net_port = free_udp_port();
    const auto load = ameoto::test::run_program({"jack_load", "netmanager", "-i", "-a 127.0.0.1 -p " + std::to_string(net_port)}, 15s, master.env());
    REQUIRE_MESSAGE(load.exit_code == 0, load.out << load.err);
    std::vector<std::unique_ptr<ameoto::test::ChildProcess>> slaves;
    std::vector<std::vector<std::string>> slave_env;
    for (int k = 1; k <= 2; ++k) {
        // Named after the master, so that its clean-up (~JackServer) also removes what they leave in /dev/shm.
        const std::string name = master.name() + "-node" + std::to_string(k);
        slave_env.push_back({"JACK_DEFAULT_SERVER=" + name, "JACK_NO_AUDIO_RESERVATION=1"});
        slaves.push_back(std::make_unique<ameoto::test::ChildProcess>(std::vector<std::string>{
            "/usr/bin/jackd", "--realtime", "-n", name, "-d", "net", "-a", "127.0.0.1", "-p", std::to_string(net_port), "-n",
            "node" + std::to_string(k), "-C", "2", "-P", "2", "-l", "2"}));
        REQUIRE_MESSAGE(ameoto::test::run_program({"/usr/bin/jack_wait", "-w", "-t", "10"}, 15s, slave_env.back()).exit_code == 0,
                        slaves.back()->output());
    }
    for (const char* p : {"node1:from_slave_1", "node1:from_slave_2", "node2:from_slave_1", "node2:from_slave_2"}) {
        bool there = false;
        for (int tries = 0; tries < 50 && !there; ++tries) {
            there = lsp_has(master.env(), p);
            if (!there) std::this_thread::sleep_for(100ms);
        }
        REQUIRE_MESSAGE(there, p << " on the master");
    }

    // A take whose first 0.25 s of rain met an xrun, or whose servers lost a cycle from the nodes' start on
    // (a loaded machine), is played again, at most 3 times.
    for (int take = 1; take <= 3; ++take) {
        // Where the servers' logs stand before this take's nodes start: what they report from here on
        // (the nodes' start included: a cycle lost then shifts a node before its rain) disturbs the take.
        std::vector<std::size_t> log_from{master.output().size()};
        for (auto& s : slaves) log_from.push_back(s->output().size());
        auto server_trouble = [&] {
            int n = trouble_lines(master.output(), log_from[0]);
            for (std::size_t k = 0; k < slaves.size(); ++k) n += trouble_lines(slaves[k]->output(), log_from[k + 1]);
            return n;
        };
        ameoto::test::DaemonOptions options;
        options.listen_timeout = 30s;
        options.running_timeout = 15s;
        auto node = [&](int k, const std::vector<std::string>& more) {
            std::string name = "n";   // not "n" + to_string(k): GCC 12 warns falsely (-Wrestrict) on that form
            name += std::to_string(k);
            std::vector<std::string> args{"--backend", "jack", "--jack-name", name, "--autoconnect", "--node",
                                          std::to_string(k), "--scene", scene, "--seed", "3", "--fixed-detail", "--rain", "0"};
            args.insert(args.end(), more.begin(), more.end());
            return std::make_unique<ameoto::test::DaemonProcess>(args, slave_env[static_cast<std::size_t>(k - 1)], options);
        };
        auto two = node(2, {});
        auto one = node(1, {"--peers", "osc.udp://127.0.0.1:" + std::to_string(two->port()), "--peer-latency", "50"});

        // On the master: both nodes into the recorder's two inputs, channel by channel (JACK sums them).
        const std::string wav = (dir.path() / ("master-" + std::to_string(take) + ".wav")).string();
        ameoto::test::ChildProcess rec({"/usr/bin/jack-record", "-b", "262144", "-n", "2", "-p", "node1:from_slave_%d", "-t", "3", wav},
                                       master.env());
        std::string recorder;
        for (int tries = 0; tries < 50 && recorder.empty(); ++tries) {
            std::this_thread::sleep_for(50ms);
            const auto lsp = ameoto::test::run_program({"jack_lsp", "-c", "node1:from_slave_2"}, 10s, master.env()).out;
            if (const auto at = lsp.find(":in_2"); at != std::string::npos) {
                const auto from = lsp.rfind(' ', at) + 1;
                recorder = lsp.substr(from, at - from);
            }
        }
        REQUIRE(!recorder.empty());
        for (int c = 1; c <= 2; ++c)
            REQUIRE(ameoto::test::run_program({"jack_connect", "node2:from_slave_" + std::to_string(c), recorder + ":in_" + std::to_string(c)}, 10s,
                                              master.env())
                        .exit_code == 0);

        ameoto::test::OscTestClient c(one->port());
        bool answering = false;
        for (int tries = 0; tries < 30 && !answering; ++tries) {
            const auto r = c.request("/nodes", {}, "/nodes.reply", 2s);
            answering = r && r->args.size() == 15 && r->args[9].integer == 1;
            if (!answering) std::this_thread::sleep_for(100ms);
        }
        REQUIRE(answering);
        const auto x1 = ameoto::test::status_reply(c).args[6].integer;
        ameoto::test::OscTestClient c2(two->port());
        const auto x2 = ameoto::test::status_reply(c2).args[6].integer;
        c.send("/rain/rate", {OscArgument::from_float(10.0f)});   // to the conductor only
        REQUIRE_MESSAGE(rec.wait(ameoto::test::scaled(20s)) == 0, rec.output());
        const std::int64_t node_xruns = ameoto::test::status_reply(c).args[6].integer - x1 + ameoto::test::status_reply(c2).args[6].integer - x2;
        const int trouble = server_trouble();
        const std::int64_t xruns = node_xruns + trouble;
        CHECK(ameoto::test::status_reply(c2).args[11].number == doctest::Approx(10.0));   // the peer got it

        const auto sum = ameoto::test::read_wav(wav);
        REQUIRE_MESSAGE(sum.ok, sum.error);
        const long long sum_onset = sum.first_nonzero_frame();
        REQUIRE(sum_onset >= 0);   // the nodes' audio arrived on the master
        const long long shift = sum_onset - whole_onset;
        REQUIRE(shift > -whole_onset);
        const float bound = 8.0f * std::numeric_limits<float>::epsilon() * whole.peak();
        float worst = 0.0f;
        long long frames = 0, first_bad = -1;
        for (long long n = whole_onset; n < whole.frames && n + shift < sum.frames; ++n, ++frames)
            for (int ch = 0; ch < 2; ++ch) {
                const float d = std::abs(sum.samples[static_cast<std::size_t>((n + shift) * 2 + ch)] - whole.samples[static_cast<std::size_t>(n * 2 + ch)]);
                if (d > bound && first_bad < 0) first_bad = n - whole_onset;
                worst = std::max(worst, d);
            }
        MESSAGE("take " << take << ": on the master, the two nodes' rain against the whole scene's over " << frames
                        << " frames from its first sound: largest difference " << worst << " (bound " << bound << "); xruns " << node_xruns << " on the nodes during the rain, "
                        << trouble << " cycles the servers logged as gone wrong since the nodes started");
        REQUIRE(frames > 24000);
        const long long agreed = first_bad < 0 ? frames : first_bad;
        INFO("the sum agrees with the whole for " << agreed << " frames from the first sound");
        CHECK(one->process().stop(SIGTERM, 5s) == 0);
        CHECK(two->process().stop(SIGTERM, 5s) == 0);
        if (xruns == 0) {
            CHECK(worst <= bound);
        } else if (agreed >= 12000) {
            // An xrun skips a cycle on one server: from there one node is shifted against the other (seen:
            // agreement for 56 893 frames, then an xrun). Before it, both started their rain on one frame:
            // a node off by even one frame differs within the first drops (5 000 a second here). A cycle
            // lost before the rain (seen on CI: none on the nodes during it, agreement for 168 frames)
            // shifts a node from its first drop: that take is played again.
            MESSAGE("xruns or lost cycles in the take: the sum agreed for the " << agreed << " frames before the first one");
        } else if (take < 3) {
            continue;
        } else {
            WARN_MESSAGE(false, "every take met an xrun or a lost cycle before or within its first 0.25 s of rain: the frames could not be compared (the machine is too loaded)");
        }
        break;
    }
    for (auto& s : slaves) s->stop(SIGTERM, 5s);
    ameoto::test::run_program({"jack_unload", "netmanager"}, 10s, master.env());   // or the master's exit waits 6 s
}
