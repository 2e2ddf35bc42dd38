#pragma once
// Test helpers that run the real programs: ameotod as a guarded background process, ameoto as a
// subprocess whose exit status and output the tests look at.
//
// Interface:
//   ServerProcess server = ServerProcess::start({"--backend", "null", ...});   // throws on failure
//   server.port();                      // learnt from "ameotod: listening on osc.udp://127.0.0.1:PORT/"
//   server.wait_exit(2.0);              // exit status once it stopped by itself, nullopt on timeout
//   // ~ServerProcess: SIGTERM, then SIGKILL after 2 s, always reaped: no test leaves a daemon behind
//
//   ProgramRun r = run_program({AMEOTO_BIN_DIR "/ameoto", "status"}, 5.0);   // killed after 5 s
//   r.exit_code, r.out, r.err, r.seconds
//
//   int port = closed_udp_port();       // a port on 127.0.0.1 that nothing listens on (just freed)
//
// Children get the test's environment minus AMEOTO_HOST and AMEOTO_PORT, so a developer's shell
// settings cannot point the tests at another server. They also get PR_SET_PDEATHSIG, so even a
// test binary killed outright takes its daemon with it.

#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

namespace ameoto::test {

struct ProgramRun {
    int exit_code = -1;   // -1 when killed by a signal (including the timeout)
    bool timed_out = false;
    std::string out, err;
    double seconds = 0.0;
};

ProgramRun run_program(const std::vector<std::string>& argv, double timeout_s);

class ServerProcess {
public:
    static ServerProcess start(const std::vector<std::string>& arguments);
    ServerProcess(ServerProcess&& other) noexcept;
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;
    ServerProcess& operator=(ServerProcess&&) = delete;
    ~ServerProcess();

    int port() const { return port_; }
    const std::string& output() const { return output_; }   // what it printed so far (up to the listening line)
    std::optional<int> wait_exit(double timeout_s);

private:
    ServerProcess(pid_t pid, int out_fd) : pid_(pid), out_fd_(out_fd) {}
    void stop();
    pid_t pid_ = -1;
    int out_fd_ = -1;
    int port_ = 0;
    std::string output_;
    std::optional<int> exit_code_;
};

int closed_udp_port();

}  // namespace ameoto::test
