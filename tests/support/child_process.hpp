#pragma once
// Runs a program for a test, with its output captured, and never leaves it behind.
//
// Interface:
//   ChildProcess p({"/path/ameotod", "--port", "0"}, {"ENV=value"});   // stdout+stderr to a pipe
//   std::optional<std::string> line = p.wait_for_line("listening on", 5s);   // the whole line
//   p.output();                 // everything read so far
//   int status = p.stop(SIGTERM, 5s);   // signal, wait; SIGKILL after the timeout; returns exit code
//   p.wait(10s)                 // for a program that ends by itself; -1 on timeout
//   ~ChildProcess               // SIGTERM, then SIGKILL: a failed assertion never leaks a process

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <sys/types.h>

namespace ameoto::test {

class ChildProcess {
public:
    ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env = {});
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    std::optional<std::string> wait_for_line(const std::string& needle, std::chrono::milliseconds timeout);
    const std::string& output();
    int stop(int signal, std::chrono::milliseconds timeout);
    int wait(std::chrono::milliseconds timeout);
    void signal(int sig);
    pid_t pid() const { return pid_; }
    bool running();

private:
    bool read_some(std::chrono::milliseconds timeout);
    pid_t pid_ = -1;
    int out_fd_ = -1;
    std::string output_;
    std::size_t scanned_ = 0;   // wait_for_line looks only at lines after the last match
    int exit_code_ = -1;
    bool reaped_ = false;
};

// A path in a fresh temporary folder that the test owns (removed by the caller if it wants).
std::string temp_path(const std::string& name);

}  // namespace ameoto::test
