// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The built ameotod as a test's server: on a free port, ready to be talked to, never left behind.
//
// Interface:
//   DaemonProcess d({"--backend", "null", "--output", "-"}, {"ENV=value"});   // AMEOTO_BIN_DIR/ameotod ARGS --port 0
//                                                                         // (and --level physical unless ARGS name a --level)
//   d.port()             // from "ameotod: listening on osc.udp://ADDRESS:PORT/"
//   d.listening_line()   // that whole line
//   d.tcp_port()         // from "ameotod: listening on osc.tcp://ADDRESS:PORT/" (given --tcp-port); -1 without
//   d.process()          // its ChildProcess: stop, wait, signal, wait_for_line, output
//   ~DaemonProcess       // SIGTERM, then SIGKILL (~ChildProcess)
//
//   DaemonOptions o;     // all optional:
//   o.listen_timeout = 15s;        // for the listening line (default 30 s)
//   o.running_timeout = 10s;       // then for "running" (default 10 s)
//   o.ready_line = "...";          // wait for this line instead of "running" (e.g. --start-at's "silent until")
//   o.child.unset_env = {...};     // ChildOptions for the process
//   o.wrapper = {"pw-jack"};       // a program that runs ameotod: WRAPPER... AMEOTO_BIN_DIR/ameotod ARGS
//   DaemonProcess d(args, env, o);
//
// The constructor returns once ameotod has said "running" after the listening line; when either
// does not come in time it throws std::runtime_error with everything ameotod printed.
//
//   int port = port_from_listening_line("ameotod: listening on osc.udp://127.0.0.1:7770/");   // 7770

#include <chrono>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"

namespace ameoto::test {

struct DaemonOptions {
    // ameotod builds its scene (about 2.5 s of CPU) before it listens; on a
    // shared, loaded machine that has taken up to 30 s of wall time. Both waits stretch under the
    // sanitizers (ChildProcess, timing_scale.hpp).
    std::chrono::milliseconds listen_timeout{30000};
    std::chrono::milliseconds running_timeout{10000};
    ChildOptions child;
    std::vector<std::string> wrapper;
    std::string ready_line = "running";

    // For tests that start ameotod many times beside others' builds: 30 s to listen and 30 s until
    // its first "running" line (both stretched under the sanitizers).
    static DaemonOptions patient() {
        DaemonOptions o;
        o.running_timeout = std::chrono::milliseconds(30000);
        return o;
    }
};

class DaemonProcess {
public:
    explicit DaemonProcess(std::vector<std::string> arguments, const std::vector<std::string>& env = {},
                           const DaemonOptions& options = {});
    DaemonProcess(const DaemonProcess&) = delete;
    DaemonProcess& operator=(const DaemonProcess&) = delete;

    int port() const { return port_; }
    const std::string& listening_line() const { return listening_line_; }
    int tcp_port() const { return tcp_port_; }
    ChildProcess& process() { return process_; }

private:
    ChildProcess process_;
    std::string listening_line_;
    int port_ = -1;
    int tcp_port_ = -1;
};

// The port in a line "ameotod: listening on osc.udp://127.0.0.1:PORT/"; -1 without one.
int port_from_listening_line(const std::string& line);

}  // namespace ameoto::test
