// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "tests/support/timing_scale.hpp"

extern char** environ;

namespace ameoto::test {
namespace {

using Clock = std::chrono::steady_clock;

std::string name_of(const std::string& entry) { return entry.substr(0, entry.find('=')); }

// "NAME=value" names one of `names` (exactly, or by a prefix ending in '*').
bool named_in(const std::string& entry, const std::vector<std::string>& names) {
    const std::string name = name_of(entry);
    for (const auto& n : names) {
        const bool prefix = !n.empty() && n.back() == '*';
        if (prefix ? name.starts_with(n.substr(0, n.size() - 1)) : name == n) return true;
    }
    return false;
}

// argv[0] as execvp would find it, resolved here because the child may not allocate.
std::string find_program(const std::string& name) {
    if (name.find('/') != std::string::npos) return name;
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/bin:/usr/bin";
    for (std::size_t start = 0; start <= dirs.size();) {
        std::size_t end = dirs.find(':', start);
        if (end == std::string::npos) end = dirs.size();
        const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
        const std::string candidate = dir + "/" + name;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
        start = end + 1;
    }
    return name;   // execve fails with ENOENT, and the caller hears of it
}

// Everything the child needs, built before fork: between fork and exec it may only make
// async-signal-safe calls.
struct ExecImage {
    std::string program;
    std::vector<std::string> argv_strings, env_strings;
    std::vector<char*> argv, envp;
    ExecImage(const std::vector<std::string>& arguments, const std::vector<std::string>& extra_env, const ChildOptions& options)
        : argv_strings(arguments) {
        if (arguments.empty()) throw std::runtime_error("ChildProcess: empty argv");
        program = find_program(arguments[0]);
        for (char** e = environ; *e; ++e) {
            const std::string entry = *e;
            if (named_in(entry, options.unset_env)) continue;
            bool replaced = false;
            for (const auto& x : extra_env) replaced |= name_of(x) == name_of(entry);
            if (!replaced) env_strings.push_back(entry);
        }
        env_strings.insert(env_strings.end(), extra_env.begin(), extra_env.end());
        for (auto& s : argv_strings) argv.push_back(s.data());
        argv.push_back(nullptr);
        for (auto& s : env_strings) envp.push_back(s.data());
        envp.push_back(nullptr);
    }
};

void make_pipe(int fds[2]) {
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
}

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env,
                           const ChildOptions& options) {
    const ExecImage image(argv, extra_env, options);
    int out[2] = {-1, -1}, err[2] = {-1, -1}, exec_error[2] = {-1, -1};
    make_pipe(out);
    if (options.separate_stderr) make_pipe(err);
    make_pipe(exec_error);   // stays empty when execve succeeds: O_CLOEXEC closes it
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ == 0) {
        if (options.die_with_parent) {
            prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (getppid() != parent) _exit(127);   // the test died before prctl took effect
        }
        const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
        if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
        dup2(out[1], STDOUT_FILENO);
        dup2(options.separate_stderr ? err[1] : out[1], STDERR_FILENO);
        execve(image.program.c_str(), image.argv.data(), image.envp.data());
        const int e = errno;
        (void)!write(exec_error[1], &e, sizeof e);
        _exit(127);
    }
    const int fork_errno = errno;
    close(out[1]);
    if (err[1] >= 0) close(err[1]);
    close(exec_error[1]);
    out_fd_ = out[0];
    err_fd_ = err[0];
    int child_errno = pid_ < 0 ? fork_errno : 0;
    if (pid_ > 0) {
        ssize_t n;
        while ((n = read(exec_error[0], &child_errno, sizeof child_errno)) < 0 && errno == EINTR) {}
        if (n != static_cast<ssize_t>(sizeof child_errno)) child_errno = 0;
    }
    close(exec_error[0]);
    if (child_errno != 0) {
        if (pid_ > 0)
            while (waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {}
        close(out_fd_);
        if (err_fd_ >= 0) close(err_fd_);
        throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(child_errno));
    }
}

ChildProcess::~ChildProcess() {
    if (!reaped_) stop(SIGTERM, std::chrono::milliseconds(3000));
    // Closed only now: a program printing on its way out would get SIGPIPE from a closed pipe.
    if (out_fd_ >= 0) close(out_fd_);
    if (err_fd_ >= 0) close(err_fd_);
}

// Waits up to `timeout` for output on either pipe and reads what is there; true when it got any.
bool ChildProcess::read_some(std::chrono::milliseconds timeout) {
    pollfd p[2] = {{out_closed_ ? -1 : out_fd_, POLLIN, 0}, {err_fd_ < 0 || err_closed_ ? -1 : err_fd_, POLLIN, 0}};
    if (poll(p, 2, static_cast<int>(timeout.count())) <= 0) return false;
    bool got = false;
    auto take = [&](const pollfd& fd, std::string& into, bool& closed) {
        if (fd.fd < 0 || fd.revents == 0) return;
        char buffer[4096];
        const ssize_t n = read(fd.fd, buffer, sizeof buffer);
        if (n > 0) {
            into.append(buffer, static_cast<std::size_t>(n));
            got = true;
        } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
            closed = true;
        }
    };
    take(p[0], output_, out_closed_);
    take(p[1], error_output_, err_closed_);
    return got;
}

// The waits for a program (a line, its end) are the bounds that depend on the machine's speed: they
// stretch under the sanitizers (timing_scale.hpp) and nowhere else.
std::optional<std::string> ChildProcess::wait_for_line(const std::string& needle, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + scaled(timeout);
    for (;;) {
        std::size_t start = scanned_;
        std::size_t end;
        while ((end = output_.find('\n', start)) != std::string::npos) {
            const std::string line = output_.substr(start, end - start);
            start = end + 1;
            if (line.find(needle) != std::string::npos) {
                scanned_ = start;
                return line;
            }
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) return std::nullopt;
        if (!read_some(left) && !running()) {
            // Drain whatever is left after exit, then give up.
            while (read_some(std::chrono::milliseconds(0))) {}
            if (output_.find(needle, scanned_) == std::string::npos) return std::nullopt;
        }
    }
}

const std::string& ChildProcess::output() {
    while (read_some(std::chrono::milliseconds(0))) {}
    return output_;
}

const std::string& ChildProcess::error_output() {
    while (read_some(std::chrono::milliseconds(0))) {}
    return error_output_;
}

bool ChildProcess::running() {
    if (reaped_) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
        reaped_ = true;
        raw_status_ = status;
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        return false;
    }
    return true;
}

void ChildProcess::signal(int sig) {
    if (!reaped_) kill(pid_, sig);
}

int ChildProcess::wait(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + scaled(timeout);
    while (running()) {
        if (Clock::now() > deadline) return -1;
        read_some(std::chrono::milliseconds(10));
    }
    return exit_code_;
}

int ChildProcess::stop(int sig, std::chrono::milliseconds timeout) {
    signal(sig);
    const int code = wait(timeout);
    if (code != -1) return code;
    signal(SIGKILL);
    return wait(std::chrono::milliseconds(5000));
}

ProgramRun run_program(const std::vector<std::string>& argv, std::chrono::milliseconds timeout,
                       const std::vector<std::string>& extra_env, const ChildOptions& options) {
    ProgramRun run;
    const auto start = Clock::now();
    std::optional<ChildProcess> child;
    try {
        child.emplace(argv, extra_env, options);
    } catch (const std::runtime_error& e) {
        (options.separate_stderr ? run.err : run.out) = e.what();
        run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        return run;
    }
    if (child->wait(timeout) == -1) {
        run.timed_out = true;
        child->stop(SIGKILL, std::chrono::milliseconds(5000));
    }
    run.out = child->output();
    run.err = child->error_output();
    const int status = child->exit_status();
    run.exit_code = !run.timed_out && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return run;
}

}  // namespace ameoto::test
