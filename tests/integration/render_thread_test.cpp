// SPDX-License-Identifier: GPL-3.0-or-later
// The null backend's render thread as the kernel sees it: its name, and the scheduling that
// --realtime-priority asks for (server/backends/null_backend.hpp, "Scheduling"), read from
// /proc/PID/task/TID/stat, the same fields `ps -L -o rtprio,policy` prints.

#include <doctest/doctest.h>
#include <sched.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/daemon_process.hpp"

using namespace std::chrono_literals;
using Daemon = ameoto::test::DaemonProcess;

namespace {

struct ThreadScheduling {
    int policy = -1;     // SCHED_OTHER 0, SCHED_FIFO 1, ...
    int priority = -1;   // rt_priority: 1..99 under SCHED_FIFO, 0 otherwise
};

// The thread of `pid` named `name`, or none. stat's second field is the name in parentheses; policy
// and rt_priority are fields 41 and 40 (proc(5)), counted after the closing parenthesis.
std::optional<ThreadScheduling> thread_named(int pid, const std::string& name) {
    const std::string tasks = "/proc/" + std::to_string(pid) + "/task";
    for (const auto& task : std::filesystem::directory_iterator(tasks)) {
        std::ifstream comm(task.path() / "comm");
        std::string thread_name;
        std::getline(comm, thread_name);
        if (thread_name != name) continue;
        std::ifstream stat_file(task.path() / "stat");
        std::string stat((std::istreambuf_iterator<char>(stat_file)), {});
        const auto close = stat.rfind(')');
        if (close == std::string::npos) return std::nullopt;
        std::istringstream fields(stat.substr(close + 2));   // field 3 (state) onwards
        std::vector<std::string> f{"", "", ""};               // fields 0..2: unused, pid, comm
        for (std::string s; fields >> s;) f.push_back(s);
        if (f.size() <= 41) return std::nullopt;
        return ThreadScheduling{std::stoi(f[41]), std::stoi(f[40])};
    }
    return std::nullopt;
}

// What the daemon logged about it: said right after the backend starts, so before "running", which
// the Daemon waited for.
std::string scheduling_line(Daemon& d) {
    const std::string& out = d.process().output();
    const auto at = out.find("null backend render thread:");
    if (at == std::string::npos) return "";
    return out.substr(at, out.find('\n', at) - at);
}

}  // namespace

TEST_CASE("render thread: --realtime-priority 0 keeps normal scheduling, and says so") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--realtime-priority", "0"});
    const std::string line = scheduling_line(d);
    CHECK(line.find("normal scheduling (--realtime-priority 0)") != std::string::npos);
    const auto thread = thread_named(d.process().pid(), "ameoto-render");
    REQUIRE(thread);
    CHECK(thread->policy == SCHED_OTHER);
    CHECK(thread->priority == 0);
}

TEST_CASE("render thread: paced, it asks for SCHED_FIFO at the priority given; refused, it runs normally and the log says why") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--realtime-priority", "42"});
    const std::string line = scheduling_line(d);
    const auto thread = thread_named(d.process().pid(), "ameoto-render");
    REQUIRE(thread);
    INFO(line);
    // What the kernel grants depends on who runs the test: root (CI) or an rtprio limit of 42 or more
    // gets it; anyone else is refused, which must leave the thread running and be reported.
    if (thread->policy == SCHED_FIFO) {
        CHECK(thread->priority == 42);
        CHECK(line.find("SCHED_FIFO priority 42") != std::string::npos);
        CHECK(line.find("refused") == std::string::npos);
    } else {
        CHECK(thread->policy == SCHED_OTHER);
        CHECK(line.find("SCHED_FIFO priority 42 refused") != std::string::npos);
    }
    if (geteuid() == 0) CHECK(thread->policy == SCHED_FIFO);   // root may always
}

TEST_CASE("render thread: an offline render keeps normal scheduling") {
    Daemon d({"--backend", "null", "--output", "-", "--offline", "--duration", "600", "--realtime-priority", "80"});
    const std::string line = scheduling_line(d);
    CHECK(line.find("normal scheduling (offline render)") != std::string::npos);
    const auto thread = thread_named(d.process().pid(), "ameoto-render");
    REQUIRE(thread);
    CHECK(thread->policy == SCHED_OTHER);
}
