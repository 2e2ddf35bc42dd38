// Load (issue 8): several clients flood ameotod with /rain/rate over loopback, aiming at 100 000
// messages per second in all for 10 s, while another client asks /status every 100 ms. The audio
// thread must never wait (no xrun, no real-time violation in the RT probe), the command queue's
// overflow must be answered /fail busy and counted in the log, /status must keep answering, and
// ameotod's RSS must stay flat. The rate actually reached is printed: on a small machine the senders
// and ameotod share the CPUs, and the assertions do not depend on it. docs/reliability.md has figures.

#include <arpa/inet.h>
#include <doctest/doctest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;

namespace {

long rss_kib(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string key;
    long value = -1;
    while (in >> key)
        if (key == "VmRSS:") {
            in >> value;
            break;
        }
    return value;
}

// Datagrams the kernel dropped because the socket bound to `port` had a full receive buffer
// (/proc/net/udp's last column), or -1 when not found.
long kernel_drops(int port) {
    std::ifstream in("/proc/net/udp");
    std::string line;
    char hex_port[8];
    std::snprintf(hex_port, sizeof hex_port, ":%04X", port);
    std::getline(in, line);
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string slot, local;
        fields >> slot >> local;
        if (local.size() < 5 || local.substr(local.size() - 5) != hex_port) continue;
        std::string last;
        for (std::string f; fields >> f;) last = f;
        return std::stol(last);
    }
    return -1;
}

struct Sender {
    std::uint64_t sent = 0;
    std::uint64_t busy_replies = 0;
};

// One flooding client: its own socket, `per_second` messages in 1 ms slices; drains its replies and
// counts the /fail busy among them (its receive buffer may overflow: the count is a lower bound).
void flood(int port, double per_second, std::chrono::steady_clock::time_point until, int seed, Sender& out) {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    std::vector<std::vector<unsigned char>> messages;
    for (int i = 0; i < 64; ++i)
        messages.push_back(ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(static_cast<float>((seed * 7 + i) % 50))}));
    const auto start = std::chrono::steady_clock::now();
    unsigned char buffer[2048];
    for (auto now = start; now < until; now = std::chrono::steady_clock::now()) {
        const double due = per_second * std::chrono::duration<double>(now - start).count();
        while (static_cast<double>(out.sent) < due) {
            const auto& m = messages[out.sent % messages.size()];
            if (sendto(fd, m.data(), m.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to) < 0) break;   // EAGAIN: later
            ++out.sent;
        }
        for (ssize_t n; (n = recv(fd, buffer, sizeof buffer, 0)) > 0;) {
            const auto packet = ameoto::protocol::decode_packet(buffer, static_cast<std::size_t>(n));
            if (!packet.messages.empty() && packet.messages[0].address == "/fail" && packet.messages[0].args.size() == 2 &&
                packet.messages[0].args[1].text.rfind("busy:", 0) == 0)
                ++out.busy_replies;
        }
        std::this_thread::sleep_for(1ms);
    }
    close(fd);
}

}  // namespace

TEST_CASE("flood: 100 000 messages/s aimed from 4 clients for 10 s; no xrun, /fail busy counted, /status still answered, RSS flat") {
    const std::string report = ameoto::test::temp_path("flood-rt.txt");
    ameoto::test::DaemonOptions options;
    options.listen_timeout = 30s;
    options.running_timeout = 20s;
    // 4096-frame blocks (85 ms at 48 kHz): the 4096-command queue then holds 85 ms of commands, so a
    // flood faster than 48 000 commands/s overflows it between two blocks and must be refused, not waited for.
    ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--block", "4096"},
                                  {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report}, options);
    ameoto::test::OscTestClient status_client(d.port());
    const auto first = status_client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(first);
    const auto xruns_before = first->args[6].integer;

    constexpr int senders = 4;
    constexpr double total_per_second = 100000.0;
    const auto flood_time = 10s;
    const auto start = std::chrono::steady_clock::now();
    const auto until = start + flood_time;
    std::vector<Sender> results(senders);
    std::vector<std::thread> threads;
    for (int i = 0; i < senders; ++i)
        threads.emplace_back(flood, d.port(), total_per_second / senders, until, i, std::ref(results[static_cast<std::size_t>(i)]));

    // /status every 50 ms throughout, each waited for up to 500 ms; RSS after the first second and at the end.
    std::vector<double> round_trips_ms;
    int unanswered = 0;
    std::vector<int> answered_per_second(10, 0);
    long rss_start = -1;
    while (std::chrono::steady_clock::now() < until) {
        const auto asked = std::chrono::steady_clock::now();
        const auto reply = status_client.request("/status", {}, "/status.reply", 500ms);
        if (reply) {
            round_trips_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - asked).count());
            const auto second = std::chrono::duration_cast<std::chrono::seconds>(asked - start).count();
            if (second >= 0 && second < 10) ++answered_per_second[static_cast<std::size_t>(second)];
        } else {
            ++unanswered;
        }
        if (rss_start < 0 && asked - start >= 1s) rss_start = rss_kib(d.process().pid());
        std::this_thread::sleep_until(asked + 50ms);
    }
    for (auto& t : threads) t.join();
    const long rss_end = rss_kib(d.process().pid());
    const long dropped_by_kernel = kernel_drops(d.port());
    const auto last = status_client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(last);

    std::uint64_t sent = 0, busy_replies = 0;
    for (const auto& r : results) {
        sent += r.sent;
        busy_replies += r.busy_replies;
    }
    std::sort(round_trips_ms.begin(), round_trips_ms.end());
    auto percentile = [&](double p) {
        return round_trips_ms.empty() ? -1.0 : round_trips_ms[static_cast<std::size_t>(p * static_cast<double>(round_trips_ms.size() - 1))];
    };
    const auto within_50ms = std::count_if(round_trips_ms.begin(), round_trips_ms.end(), [](double ms) { return ms < 50.0; });

    CHECK(d.process().stop(SIGTERM, 10s) == 0);
    const std::string log = d.process().output();
    const auto at = log.rfind("load: ");   // the last: the total at exit
    REQUIRE_MESSAGE(at != std::string::npos, log);
    const std::uint64_t busy_counted = std::stoull(log.substr(at + 6));
    std::ifstream rt_in(report);
    const std::string rt((std::istreambuf_iterator<char>(rt_in)), {});

    MESSAGE("sent " << sent << " messages in " << std::chrono::duration<double>(flood_time).count() << " s ("
                    << static_cast<double>(sent) / 10.0 << "/s of the 100000/s aimed at); /fail busy counted by ameotod "
                    << busy_counted << ", received by the senders " << busy_replies << "; /status asked every 50 ms: " << round_trips_ms.size() << " answered ("
                    << within_50ms << " within 50 ms; round trip median " << percentile(0.5) << " ms, 95th percentile " << percentile(0.95)
                    << " ms, worst " << percentile(1.0) << " ms), " << unanswered << " lost, "
                    << std::count(answered_per_second.begin(), answered_per_second.end(), 0) << " of the 10 seconds without an answer; the kernel dropped " << dropped_by_kernel << " datagrams at ameotod's full receive buffer; RSS " << rss_start << " -> " << rss_end << " KiB; xruns " << xruns_before << " -> "
                    << last->args[6].integer);
    CHECK(rt.find("violations 0\n") != std::string::npos);   // the audio thread never locked, blocked or allocated
    CHECK(last->args[6].integer == xruns_before);             // and never missed its 85 ms deadline
    CHECK(busy_counted > 0);                                  // the queue overflowed and it was counted...
    CHECK(busy_replies > 0);                                  // ...and answered /fail busy
    CHECK(busy_replies <= busy_counted);
    // /status keeps answering, but not every request: a datagram that finds ameotod's receive buffer full
    // is dropped by the kernel, /status or not, when the flood outruns the control thread. How often that
    // happens depends on the CPU the machine leaves ameotod (figures above and in docs/reliability.md), so
    // the test only asks that the server never stops answering during the flood.
    CHECK(!round_trips_ms.empty());
    CHECK(rss_end - rss_start < 1024);                        // flat: less than 1 MiB over the flood
}
