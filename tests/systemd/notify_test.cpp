// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod's sd_notify protocol, seen from systemd's side: the test plays the service manager.
// It binds the datagram socket systemd would pass in $NOTIFY_SOCKET, starts the built ameotod with
// the null backend, and checks READY=1 (only after the port is bound and audio runs), STATUS=,
// WATCHDOG=1 at half of $WATCHDOG_USEC, STOPPING=1 on SIGTERM, a clean exit, and that every message
// comes from the main process (the units say NotifyAccess=main).
#include <doctest/doctest.h>

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/jack_server.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/timing_scale.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
using ameoto::test::ChildOptions;
using ameoto::test::ChildProcess;
using ameoto::test::TempDir;
using ameoto::test::scaled;


struct Fd {
    int fd = -1;
    explicit Fd(int f = -1) : fd(f) {}
    ~Fd() {
        if (fd >= 0) close(fd);
    }
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
};

// The socket systemd listens on: AF_UNIX datagrams, with the sender's credentials attached.
struct NotifySocket {
    Fd socket;
    std::string path;
    explicit NotifySocket(const fs::path& p) : socket(::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0)), path(p.string()) {
        REQUIRE(socket.fd >= 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        REQUIRE(path.size() < sizeof address.sun_path);
        std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
        REQUIRE_MESSAGE(bind(socket.fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0, "bind " << path << ": " << std::strerror(errno));
        const int on = 1;
        REQUIRE(setsockopt(socket.fd, SOL_SOCKET, SO_PASSCRED, &on, sizeof on) == 0);
    }
};

// ameotod, started the way systemd starts a Type=notify service: its stdout read by the test, its
// stderr kept apart. Stopped and reaped on every path out of the test (ChildProcess), so a failed
// assertion never leaves a daemon running.
ChildProcess start_daemon(const std::string& notify_socket, const std::string& watchdog_usec,
                          std::vector<std::string> backend = {"--backend", "null", "--output", "-", "--realtime"},
                          const std::vector<std::string>& more_env = {}) {
    // The daemon's own environment, with systemd's variables replaced by ours.
    ChildOptions options;
    options.unset_env = {"NOTIFY_SOCKET", "WATCHDOG_USEC", "WATCHDOG_PID", "LISTEN_*"};
    options.separate_stderr = true;
    std::vector<std::string> env{"NOTIFY_SOCKET=" + notify_socket};
    env.insert(env.end(), more_env.begin(), more_env.end());
    if (!watchdog_usec.empty()) env.push_back("WATCHDOG_USEC=" + watchdog_usec);
    // sd_watchdog_enabled() ignores WATCHDOG_USEC unless WATCHDOG_PID is the process's own pid;
    // the shell exports its pid and then becomes ameotod (exec keeps the pid), as systemd does.
    std::vector<std::string> argv{"/bin/sh", "-c",
                                  std::string(watchdog_usec.empty() ? "" : "WATCHDOG_PID=$$; export WATCHDOG_PID; ") + "exec \"$0\" \"$@\"",
                                  std::string(AMEOTO_BIN_DIR) + "/ameotod", "--port", "0"};
    argv.insert(argv.end(), backend.begin(), backend.end());
    return ChildProcess(argv, env, options);
}

// Everything the daemon said, in causal order: its stdout lines and its notify messages.
struct Event {
    enum Kind { line, notify } kind;
    std::string text;      // a stdout line, or one VARIABLE=value of a notification
    Clock::time_point at;
    pid_t sender = 0;      // notify: the sending process, from SCM_CREDENTIALS
};

struct Observer {
    NotifySocket& socket;
    ChildProcess& daemon;
    std::vector<Event> events;
    std::size_t consumed = 0;   // how much of daemon.output() has become events
    bool stdout_closed = false;

    void drain_stdout() {
        const std::string& out = daemon.output();   // reads what is in the pipe, without blocking
        for (std::size_t end; (end = out.find('\n', consumed)) != std::string::npos; consumed = end + 1)
            events.push_back({Event::line, out.substr(consumed, end - consumed), Clock::now(), 0});
        stdout_closed = daemon.output_closed();
    }

    // The notifications waiting on the socket, in the order they were sent.
    std::vector<Event> receive_notifications() {
        std::vector<Event> received;
        for (;;) {
            char data[4096];
            alignas(cmsghdr) char control[CMSG_SPACE(sizeof(ucred))];
            iovec iov{data, sizeof data - 1};
            msghdr message{};
            message.msg_iov = &iov;
            message.msg_iovlen = 1;
            message.msg_control = control;
            message.msg_controllen = sizeof control;
            const ssize_t n = recvmsg(socket.socket.fd, &message, MSG_CMSG_CLOEXEC);
            if (n < 0) return received;
            pid_t sender = 0;
            for (cmsghdr* c = CMSG_FIRSTHDR(&message); c; c = CMSG_NXTHDR(&message, c)) {
                if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_CREDENTIALS) {
                    ucred credentials{};
                    std::memcpy(&credentials, CMSG_DATA(c), sizeof credentials);
                    sender = credentials.pid;
                }
            }
            const std::string text(data, static_cast<std::size_t>(n));
            std::size_t start = 0;
            while (start < text.size()) {
                std::size_t end = text.find('\n', start);
                if (end == std::string::npos) end = text.size();
                if (end > start) received.push_back({Event::notify, text.substr(start, end - start), Clock::now(), sender});
                start = end + 1;
            }
        }
    }

    // Reads until `done()` or the timeout; true when done() became true.
    bool wait_until(const std::function<bool()>& done, Clock::duration timeout) {
        const auto deadline = Clock::now() + timeout;
        while (!done()) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
            if (left.count() <= 0) return false;
            pollfd fds[2] = {{socket.socket.fd, POLLIN, 0}, {stdout_closed ? -1 : daemon.output_fd(), POLLIN, 0}};
            poll(fds, 2, static_cast<int>(std::min<long long>(left.count(), 50)) + 1);
            // ameotod prints a line before the notification that follows from it, so once a datagram
            // has been received, every line written before it is in the pipe. Receiving first and
            // reading stdout second keeps that order; reading stdout first could miss lines the daemon
            // wrote between the two reads, just before the datagram (it did once, in CI, under the
            // sanitizers). A line written after a datagram may be placed before it; no check relies
            // on the opposite.
            std::vector<Event> received = receive_notifications();
            drain_stdout();
            events.insert(events.end(), received.begin(), received.end());
        }
        return true;
    }

    void watch_for(Clock::duration duration) {
        wait_until([] { return false; }, duration);
    }

    // Index of the first event of `kind` whose text starts with `prefix`, or -1.
    long find(Event::Kind kind, const std::string& prefix) const {
        for (std::size_t i = 0; i < events.size(); ++i)
            if (events[i].kind == kind && events[i].text.starts_with(prefix)) return static_cast<long>(i);
        return -1;
    }
    bool has(Event::Kind kind, const std::string& prefix) const { return find(kind, prefix) >= 0; }

    std::string transcript() const {
        std::string s;
        for (const auto& e : events) s += (e.kind == Event::line ? "stdout: " : "notify: ") + e.text + "\n";
        if (!daemon.error_output().empty()) s += "stderr:\n" + daemon.error_output();
        return s;
    }
};

}  // namespace

TEST_CASE("ameotod tells systemd READY, STATUS, WATCHDOG and STOPPING at the right moments") {
    TempDir dir("ameoto-notify");
    NotifySocket socket(dir.path() / "notify");
    ChildProcess daemon = start_daemon(socket.path, "400000");   // WatchdogSec=0.4s: a ping expected every 200 ms
    Observer seen{socket, daemon, {}, 0, false};
    INFO("what ameotod said so far:\n" << seen.transcript());

    // READY=1 only once the port is bound and the first audio block has run.
    REQUIRE_MESSAGE(seen.wait_until([&] { return seen.has(Event::notify, "READY=1"); }, scaled(10s)), "no READY=1 within 10 s");
    const long ready = seen.find(Event::notify, "READY=1");
    const long listening = seen.find(Event::line, "ameotod: listening on osc.udp://127.0.0.1:");
    const long running = seen.find(Event::line, "ameotod: running");
    REQUIRE(listening >= 0);
    CHECK(seen.events[static_cast<std::size_t>(listening)].text.find(":0/") == std::string::npos);   // --port 0 got a real port
    REQUIRE(running >= 0);
    CHECK(listening < running);
    CHECK(running < ready);

    // The status systemctl shows, sent with READY.
    REQUIRE(seen.wait_until([&] { return seen.has(Event::notify, "STATUS="); }, 2s));
    CHECK(seen.events[static_cast<std::size_t>(seen.find(Event::notify, "STATUS="))].text == "STATUS=playing on null");

    // WATCHDOG=1 keeps coming while audio advances: every 200 ms, so about 10 in 2 s.
    const auto watch_from = Clock::now();
    seen.watch_for(2s);
    long pings = 0;
    for (const auto& e : seen.events)
        if (e.kind == Event::notify && e.text == "WATCHDOG=1" && e.at > watch_from) ++pings;
    CHECK(pings >= 3);
    CHECK(pings <= 15);   // half the interval, not a flood
    CHECK_FALSE(seen.has(Event::notify, "STOPPING=1"));

    // SIGTERM: STOPPING=1, then a clean exit.
    REQUIRE(kill(daemon.pid(), SIGTERM) == 0);
    CHECK_MESSAGE(seen.wait_until([&] { return seen.has(Event::notify, "STOPPING=1"); }, 5s), "no STOPPING=1 within 5 s of SIGTERM");
    REQUIRE_MESSAGE(daemon.wait(5s) != -1, "ameotod still runs 5 s after SIGTERM");
    seen.wait_until([&] { return seen.stdout_closed; }, 1s);
    CHECK(WIFEXITED(daemon.exit_status()));
    CHECK(WEXITSTATUS(daemon.exit_status()) == 0);
    CHECK(seen.has(Event::line, "ameotod: stopped"));
    CHECK(seen.find(Event::notify, "STOPPING=1") > ready);

    // NotifyAccess=main: systemd drops messages from any other process.
    for (const auto& e : seen.events)
        if (e.kind == Event::notify) CHECK_MESSAGE(e.sender == daemon.pid(), e.text << " came from pid " << e.sender << ", not " << daemon.pid());
}

TEST_CASE("without a watchdog in the environment ameotod sends no WATCHDOG=1") {
    TempDir dir("ameoto-notify");
    NotifySocket socket(dir.path() / "notify");
    ChildProcess daemon = start_daemon(socket.path, "");
    Observer seen{socket, daemon, {}, 0, false};
    INFO("what ameotod said so far:\n" << seen.transcript());

    REQUIRE_MESSAGE(seen.wait_until([&] { return seen.has(Event::notify, "READY=1"); }, scaled(10s)), "no READY=1 within 10 s");
    seen.watch_for(600ms);   // with the watchdog of the test above, this would hold 3 pings
    CHECK_FALSE(seen.has(Event::notify, "WATCHDOG="));

    REQUIRE(kill(daemon.pid(), SIGTERM) == 0);
    CHECK(seen.wait_until([&] { return seen.has(Event::notify, "STOPPING=1"); }, 5s));
    REQUIRE(daemon.wait(5s) != -1);
    CHECK(WIFEXITED(daemon.exit_status()));
    CHECK(WEXITSTATUS(daemon.exit_status()) == 0);
}

TEST_CASE("WATCHDOG=1 stops while audio stalls (JACK server gone) and resumes when it plays again") {
    // The rule: the watchdog is fed only while the audio cycle advances, so systemd restarts a
    // daemon whose audio is stuck. A real jackd (dummy driver) is stopped to stall the audio thread.
    ameoto::test::JackServer jack;
    TempDir dir("ameoto-notify");
    NotifySocket socket(dir.path() / "notify");
    ChildProcess daemon = start_daemon(socket.path, "400000", {"--backend", "jack", "--jack-name", "ameoto_wd"}, jack.env());
    Observer seen{socket, daemon, {}, 0, false};
    INFO("what ameotod said so far:\n" << seen.transcript());
    REQUIRE_MESSAGE(seen.wait_until([&] { return seen.has(Event::notify, "READY=1"); }, 15s), "no READY=1 within 15 s");

    auto pings_between = [&](Clock::time_point from, Clock::time_point to) {
        long n = 0;
        for (const auto& e : seen.events)
            if (e.kind == Event::notify && e.text == "WATCHDOG=1" && e.at > from && e.at <= to) ++n;
        return n;
    };
    auto t0 = Clock::now();
    seen.watch_for(1s);
    CHECK(pings_between(t0, Clock::now()) >= 2);            // playing: fed every 200 ms

    jack.stop();
    REQUIRE(seen.wait_until([&] { return seen.has(Event::notify, "STATUS=waiting for the JACK server"); }, 10s));
    seen.watch_for(300ms);                                   // a ping already under way may still land
    t0 = Clock::now();
    seen.watch_for(1500ms);
    CHECK(pings_between(t0, Clock::now()) == 0);             // stalled: no ping for 1.5 s (WatchdogSec 0.4 s)

    jack.start();
    REQUIRE(seen.wait_until([&] { return seen.has(Event::line, "ameotod: JACK server is back"); }, 10s));
    t0 = Clock::now();
    seen.watch_for(1s);
    CHECK(pings_between(t0, Clock::now()) >= 2);            // playing again: fed again
}
