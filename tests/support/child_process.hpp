// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Runs a program for a test, with its output captured, and never leaves it behind.
//
// Interface:
//   ChildProcess p({"/path/ameotod", "--port", "0"}, {"ENV=value"});   // stdout+stderr to a pipe
//   std::optional<std::string> line = p.wait_for_line("listening on", 5s);   // the whole line
//   p.output();                 // everything read so far (reads what is there, never blocks)
//   int status = p.stop(SIGTERM, 5s);   // signal, wait; SIGKILL after the timeout; returns exit code
//   p.wait(10s)                 // for a program that ends by itself; -1 on timeout
//                               // (wait_for_line, wait, stop and run_program wait timing_scale() times
//                               // as long in the sanitized build: timing_scale.hpp)
//   p.exit_status()             // the raw waitpid status once reaped (WIFEXITED...), -1 before
//   p.output_fd(), p.output_closed()   // for a test that polls the output with other descriptors
//   ~ChildProcess               // SIGTERM, then SIGKILL: a failed assertion never leaks a process
//
//   ChildOptions o;             // all optional:
//   o.unset_env = {"AMEOTO_PORT", "LISTEN_*"};   // dropped from the inherited environment
//   o.separate_stderr = true;   // stderr to error_output() instead of into output()
//   o.die_with_parent = true;   // (default) PR_SET_PDEATHSIG: a test killed outright takes it along
//                               // (the kernel ties it to the thread that started the child: start
//                               // children from the test's own thread, not from one that ends first)
//   ChildProcess p(argv, env, o);
//
//   ProgramRun r = run_program({"systemd-analyze", "--version"}, 5s);   // SIGKILL after 5 s
//   r.exit_code, r.timed_out, r.out, r.err, r.seconds   // exit_code -1: killed or could not start
//
// The environment is the test's own, minus unset_env, with each "NAME=value" of env replacing an
// inherited NAME. argv[0] without a '/' is looked up in PATH. stdin is /dev/null. The child is
// forked and exec'd (posix_spawn cannot set PR_SET_PDEATHSIG); everything it needs is prepared
// before fork. A program that cannot be started throws std::runtime_error from the constructor.

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <sys/types.h>

namespace ameoto::test {

struct ChildOptions {
    std::vector<std::string> unset_env;   // names, or prefixes ending in '*'
    bool separate_stderr = false;
    bool die_with_parent = true;
};

class ChildProcess {
public:
    ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env = {},
                 const ChildOptions& options = {});
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    std::optional<std::string> wait_for_line(const std::string& needle, std::chrono::milliseconds timeout);
    const std::string& output();
    const std::string& error_output();   // with separate_stderr; empty otherwise
    int stop(int signal, std::chrono::milliseconds timeout);
    int wait(std::chrono::milliseconds timeout);
    void signal(int sig);
    pid_t pid() const { return pid_; }
    bool running();
    int exit_status() const { return raw_status_; }
    int output_fd() const { return out_fd_; }
    bool output_closed() const { return out_closed_; }

private:
    bool read_some(std::chrono::milliseconds timeout);
    pid_t pid_ = -1;
    int out_fd_ = -1;
    int err_fd_ = -1;
    bool out_closed_ = false;
    bool err_closed_ = false;
    std::string output_;
    std::string error_output_;
    std::size_t scanned_ = 0;   // wait_for_line looks only at lines after the last match
    int exit_code_ = -1;
    int raw_status_ = -1;
    bool reaped_ = false;
};

struct ProgramRun {
    int exit_code = -1;   // -1 when killed by a signal (including the timeout) or not started
    bool timed_out = false;
    std::string out, err;   // err stays empty unless options.separate_stderr
    double seconds = 0.0;
};

// Runs argv to its end or the timeout. A program that cannot be started gives exit_code -1 and
// says why in err (out without separate_stderr).
ProgramRun run_program(const std::vector<std::string>& argv, std::chrono::milliseconds timeout,
                       const std::vector<std::string>& extra_env = {}, const ChildOptions& options = {});

}  // namespace ameoto::test
