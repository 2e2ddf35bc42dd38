// SPDX-License-Identifier: GPL-3.0-or-later
// Load (issue 8): several clients flood ameotod with /rain/rate over loopback, aiming at 100 000
// messages per second in all for 10 s, while two monitors ask /status every 50 ms, one over UDP (the
// flood's own port) and one over TCP (--tcp-port). The audio thread must never wait (no xrun, no
// real-time violation in the RT probe), the command queue's overflow must be answered /fail busy and
// counted in the log, the TCP monitor must get every answer, 97 % of them within 50 ms, the UDP
// monitor must keep being answered, and ameotod's RSS must stay flat. The rates actually reached are
// printed: on a small machine the senders and ameotod share the CPUs. docs/reliability.md has figures.

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

#include "protocol/osc_codec.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/process_memory.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/tcp_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/rt_report.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;

namespace {

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

// CPU seconds ameotod's control thread (the main thread: Daemon::run runs the io_context) has used,
// from /proc/PID/task/PID/stat (utime + stime, in clock ticks).
double control_thread_cpu_s(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto after_name = text.rfind(')');
    if (after_name == std::string::npos) return -1.0;
    std::istringstream fields(text.substr(after_name + 2));
    std::string f;
    for (int i = 3; i <= 13; ++i) fields >> f;   // state .. cmajflt
    long utime = 0, stime = 0;
    fields >> utime >> stime;
    return static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

// The monitor that must get through the flood: /status over TCP, true when /status.reply came in time.
bool tcp_status(ameoto::test::TcpTestClient& monitor, std::chrono::milliseconds timeout) {
    return monitor.request("/status", {}, "/status.reply", timeout).has_value();
}

// One monitor's /status round trips during the flood: asked every 50 ms, each waited for up to
// `timeout` (a request not answered by then is lost).
struct Monitor {
    std::vector<double> round_trips_ms;
    int lost = 0;

    template <typename Ask>
    void run(std::chrono::steady_clock::time_point until, std::chrono::milliseconds timeout, Ask&& ask) {
        while (std::chrono::steady_clock::now() < until) {
            const auto asked = std::chrono::steady_clock::now();
            if (ask(timeout)) round_trips_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - asked).count());
            else ++lost;
            std::this_thread::sleep_until(asked + 50ms);
        }
        std::sort(round_trips_ms.begin(), round_trips_ms.end());
    }
    int asked() const { return static_cast<int>(round_trips_ms.size()) + lost; }
    long within(double ms) const { return std::count_if(round_trips_ms.begin(), round_trips_ms.end(), [&](double t) { return t < ms; }); }
    double percentile(double p) const {
        return round_trips_ms.empty() ? -1.0 : round_trips_ms[static_cast<std::size_t>(p * static_cast<double>(round_trips_ms.size() - 1))];
    }
    std::string describe() const {
        std::ostringstream out;
        out << asked() << " asked, " << round_trips_ms.size() << " answered, " << within(50.0) << " within 50 ms, " << lost
            << " lost; round trip median " << percentile(0.5) << " ms, 95th " << percentile(0.95) << " ms, 99th " << percentile(0.99)
            << " ms, worst " << percentile(1.0) << " ms";
        return out.str();
    }
};

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

TEST_CASE("flood: 100 000 messages/s aimed from 4 clients for 10 s; no xrun, /fail busy counted, /status over TCP every answer and 97 % within 50 ms, RSS flat") {
    const std::string report = ameoto::test::temp_path("flood-rt.txt");
    ameoto::test::DaemonOptions options;
    options.listen_timeout = 30s;
    options.running_timeout = 20s;
    // 4096-frame blocks (85 ms at 48 kHz): the 4096-command queue then holds 85 ms of commands, so a
    // flood faster than 48 000 commands/s overflows it between two blocks and must be refused, not waited for.
    ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--block", "4096", "--tcp-port", "0"},
                                  {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report}, options);
    REQUIRE(d.tcp_port() > 0);
    ameoto::test::TcpTestClient tcp_monitor(d.tcp_port());
    ameoto::test::OscTestClient status_client(d.port());
    const auto first = status_client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(first);
    REQUIRE(tcp_status(tcp_monitor, 2s));
    const auto xruns_before = first->args[6].integer;
    const long drops_before = kernel_drops(d.port());
    const double cpu_before = control_thread_cpu_s(d.process().pid());

    constexpr int senders = 4;
    constexpr double total_per_second = 100000.0;
    const auto flood_time = 10s;
    const auto start = std::chrono::steady_clock::now();
    const auto until = start + flood_time;
    std::vector<Sender> results(senders);
    std::vector<std::thread> threads;
    for (int i = 0; i < senders; ++i)
        threads.emplace_back(flood, d.port(), total_per_second / senders, until, i, std::ref(results[static_cast<std::size_t>(i)]));

    // Both monitors throughout; RSS after the first second and at the end. UDP waits up to 500 ms for
    // each answer; TCP, which never loses one, up to 2 s (a later one would still count as lost).
    Monitor udp, tcp;
    std::thread tcp_thread([&] { tcp.run(until, 2000ms, [&](std::chrono::milliseconds t) { return tcp_status(tcp_monitor, t); }); });
    long rss_start = -1;
    std::thread rss_thread([&] {
        std::this_thread::sleep_until(start + 1s);
        rss_start = ameoto::test::resident_kib(d.process().pid());
    });
    udp.run(until, 500ms, [&](std::chrono::milliseconds t) { return status_client.request("/status", {}, "/status.reply", t).has_value(); });
    for (auto& t : threads) t.join();
    tcp_thread.join();
    rss_thread.join();
    const long rss_end = ameoto::test::resident_kib(d.process().pid());
    const long dropped_by_kernel = kernel_drops(d.port()) - drops_before;
    const double control_cpu_s = control_thread_cpu_s(d.process().pid()) - cpu_before;
    // Asked again if need be: right after the flood the receive buffer may still be full, and a
    // datagram arriving then is dropped by the kernel, /status or not.
    auto last = status_client.request("/status", {}, "/status.reply", 1s);
    for (int again = 0; again < 4 && !last; ++again) last = status_client.request("/status", {}, "/status.reply", 1s);
    REQUIRE_MESSAGE(last, "ameotod running: " << d.process().running() << "; its log:\n" << d.process().output());

    std::uint64_t sent = 0, busy_replies = 0;
    for (const auto& r : results) {
        sent += r.sent;
        busy_replies += r.busy_replies;
    }
    CHECK(d.process().stop(SIGTERM, 10s) == 0);
    const std::string log = d.process().output();
    const auto at = log.rfind("load: ");   // the last: the total at exit
    REQUIRE_MESSAGE(at != std::string::npos, log);
    const std::uint64_t busy_counted = std::stoull(log.substr(at + 6));
    const auto rt = ameoto::test::read_rt_report(report);
    const double read = static_cast<double>(sent) - static_cast<double>(dropped_by_kernel);

    MESSAGE("sent " << sent << " messages in 10 s (" << static_cast<double>(sent) / 10.0 << "/s of the 100000/s aimed at); the kernel dropped "
                    << dropped_by_kernel << " at ameotod's full receive buffer, so ameotod read " << read / 10.0 << "/s, using "
                    << control_cpu_s << " s of CPU on its control thread (" << (control_cpu_s > 0 ? read / control_cpu_s : 0.0)
                    << " datagrams per CPU second); /fail busy counted by ameotod " << busy_counted << ", received by the senders " << busy_replies
                    << "; /status over TCP: " << tcp.describe() << "; /status over UDP: " << udp.describe() << "; RSS " << rss_start << " -> "
                    << rss_end << " KiB; xruns " << xruns_before << " -> " << last->args[6].integer);
    CHECK(rt.no_violations());   // the audio thread never locked, blocked or allocated
    AMEOTO_CHECK_UNLESS_SANITIZED(last->args[6].integer == xruns_before);   // and never missed its 85 ms deadline
    CHECK(busy_counted > 0);                                  // the queue overflowed and it was counted...
    CHECK(busy_replies > 0);                                  // ...and answered /fail busy
    CHECK(busy_replies <= busy_counted);
    // The monitor that must get through a flood uses TCP (docs/reliability.md, "Load"): nothing is
    // lost, and at least 97 % of the answers take less than 50 ms, the bound. Not 100 %: the
    // kernel may leave any thread waiting longer on 2 CPUs shared with the senders (and, here, other
    // engineers' builds at load 12, where 98.3-100 % was measured; before the TCP endpoint had its
    // own thread, 77-99 %). Under the sanitizers every thread is several times slower and shares the
    // CPUs with another sanitized suite: the 50 ms is printed there, not asserted (91 % was measured
    // with one CPU taken by a real-time thread); every answer still has to come.
    CHECK(tcp.lost == 0);
    AMEOTO_CHECK_UNLESS_SANITIZED(tcp.within(50.0) * 100 >= 97L * tcp.asked());
    // Over UDP a /status that finds the receive buffer full is dropped by the kernel like any other
    // datagram (when the machine leaves ameotod too little CPU to read the flood), so only this is
    // asked: it keeps being answered.
    CHECK(!udp.round_trips_ms.empty());
    AMEOTO_CHECK_UNLESS_SANITIZED(rss_end - rss_start < 1024);   // flat: less than 1 MiB over the flood
}

TEST_CASE("flood: a burst through the UDP backlog keeps each sender's order; another sender's /status is answered meanwhile") {
    // 600 /rain/rate from one socket at once (most of them wait in ameotod's backlog), then that
    // socket's own query: it must see the burst's last value, so it cannot have been moved ahead of
    // the burst. 600 stays under the 4096-command queue, so none is refused busy.
    ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--realtime"});
    ameoto::test::OscTestClient burst(d.port()), monitor(d.port());
    REQUIRE(burst.request("/status", {}, "/status.reply", 2s));
    for (int i = 0; i < 600; ++i) burst.send("/rain/rate", {OscArgument::from_float(static_cast<float>(1 + i % 40))});
    burst.send("/rain/rate");
    CHECK(monitor.request("/status", {}, "/status.reply", 2s));
    const auto rate = burst.wait_for("/rain/rate.reply", 5s);
    REQUIRE(rate);
    CHECK(rate->args[0].number == doctest::Approx(1 + 599 % 40));   // exactly the last sent: a float of a small integer
    for (const auto& other : burst.others) CHECK(other.address != "/fail");
}

TEST_CASE("flood: a TCP flood is read no faster than it is handled (memory flat), and another TCP connection's /status is answered meanwhile") {
    // One connection sends /rain/rate as fast as TCP takes it for 3 s; the server hands at most 32 of
    // its packets at a time to the control thread (TcpLimits::max_unhandled), so TCP's flow control
    // holds the rest in the client. RSS must not grow by 1 MiB, and a second connection's /status
    // must still be answered every time.
    ameoto::test::DaemonProcess d({"--backend", "null", "--output", "-", "--realtime", "--tcp-port", "0"});
    REQUIRE(d.tcp_port() > 0);
    ameoto::test::TcpTestClient monitor(d.tcp_port());
    REQUIRE(tcp_status(monitor, 2s));

    ameoto::test::TcpTestClient flooding(d.tcp_port());
    std::vector<unsigned char> frames;
    for (int i = 0; i < 64; ++i) {
        const auto m = ameoto::test::TcpTestClient::framed(
            ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(static_cast<float>(i % 50))}));
        frames.insert(frames.end(), m.begin(), m.end());
    }
    const auto until = std::chrono::steady_clock::now() + 3s;
    std::atomic<std::uint64_t> sent_bytes{0};
    std::thread flooder([&] {
        while (std::chrono::steady_clock::now() < until) {
            const std::size_t n = flooding.offer_bytes(frames);
            sent_bytes += n;
            flooding.discard_received();                      // its /fail busy, if any
            if (n == 0) std::this_thread::sleep_for(1ms);     // the server is not reading: flow control
        }
    });
    Monitor status;
    std::this_thread::sleep_for(500ms);
    const long rss_start = ameoto::test::resident_kib(d.process().pid());
    status.run(until, 2000ms, [&](std::chrono::milliseconds t) { return tcp_status(monitor, t); });
    flooder.join();
    const long rss_end = ameoto::test::resident_kib(d.process().pid());
    MESSAGE("TCP flood: " << sent_bytes.load() / 1024 << " KiB sent in 3 s; /status on another connection: " << status.describe() << "; RSS "
                          << rss_start << " -> " << rss_end << " KiB");
    CHECK(sent_bytes.load() > 1024 * 1024);   // it was a flood
    CHECK(status.lost == 0);
    AMEOTO_CHECK_UNLESS_SANITIZED(rss_end - rss_start < 1024);
    CHECK(d.process().stop(SIGTERM, 10s) == 0);
}
