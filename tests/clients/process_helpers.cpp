#include "process_helpers.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <regex>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace ameoto::test {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// argv and envp built before fork: the child may only make async-signal-safe calls.
struct ExecImage {
    std::vector<std::string> argv_strings, env_strings;
    std::vector<char*> argv, envp;
    explicit ExecImage(const std::vector<std::string>& arguments) : argv_strings(arguments) {
        for (char** e = environ; *e; ++e) {
            const std::string entry = *e;
            if (entry.starts_with("AMEOTO_HOST=") || entry.starts_with("AMEOTO_PORT=")) continue;
            env_strings.push_back(entry);
        }
        for (auto& s : argv_strings) argv.push_back(s.data());
        argv.push_back(nullptr);
        for (auto& s : env_strings) envp.push_back(s.data());
        envp.push_back(nullptr);
    }
};

// Forks and execs with stdin from /dev/null and stdout/stderr to the given descriptors.
pid_t spawn(const ExecImage& image, int out_fd, int err_fd) {
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent) _exit(127);   // the test died before prctl took effect
        const int null_fd = open("/dev/null", O_RDONLY);
        if (null_fd >= 0) dup2(null_fd, 0);
        dup2(out_fd, 1);
        dup2(err_fd, 2);
        execve(image.argv[0], image.argv.data(), image.envp.data());
        _exit(127);
    }
    return pid;
}

void make_pipe(int fds[2]) {
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
}

// Reads what is there without blocking; false at end of file.
bool drain(int fd, std::string& into) {
    char buffer[4096];
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n > 0) into.append(buffer, static_cast<std::size_t>(n));
    return n != 0 && !(n < 0 && errno != EINTR && errno != EAGAIN);
}

int decode_status(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

}  // namespace

ProgramRun run_program(const std::vector<std::string>& argv, double timeout_s) {
    ProgramRun run;
    const auto start = Clock::now();
    int out[2], err[2];
    make_pipe(out);
    make_pipe(err);
    const ExecImage image(argv);
    const pid_t pid = spawn(image, out[1], err[1]);
    close(out[1]);
    close(err[1]);
    bool out_open = true, err_open = true;
    while (out_open || err_open) {
        const int left_ms = static_cast<int>((timeout_s - seconds_since(start)) * 1000);
        if (left_ms <= 0) {
            run.timed_out = true;
            kill(pid, SIGKILL);
            break;
        }
        pollfd p[2] = {{out_open ? out[0] : -1, POLLIN, 0}, {err_open ? err[0] : -1, POLLIN, 0}};
        if (poll(p, 2, left_ms) < 0 && errno != EINTR) break;
        if (out_open && p[0].revents) out_open = drain(out[0], run.out);
        if (err_open && p[1].revents) err_open = drain(err[0], run.err);
    }
    close(out[0]);
    close(err[0]);
    int status = 0;
    waitpid(pid, &status, 0);   // both pipes closed or the child killed: it is gone or going
    run.exit_code = run.timed_out ? -1 : decode_status(status);
    run.seconds = seconds_since(start);
    return run;
}

ServerProcess ServerProcess::start(const std::vector<std::string>& arguments) {
    int out[2];
    make_pipe(out);
    const ExecImage image(arguments);
    const pid_t pid = spawn(image, out[1], out[1]);
    close(out[1]);
    ServerProcess server(pid, out[0]);   // from here on the destructor stops it, whatever happens
    const std::regex listening(R"(ameotod: listening on osc\.udp://127\.0\.0\.1:(\d+)/)");
    const auto start = Clock::now();
    for (;;) {
        std::smatch m;
        if (std::regex_search(server.output_, m, listening)) {
            server.port_ = std::stoi(m[1]);
            return server;
        }
        const int left_ms = static_cast<int>((5.0 - seconds_since(start)) * 1000);
        if (left_ms <= 0) throw std::runtime_error("ameotod did not say where it listens within 5 s; it printed:\n" + server.output_);
        pollfd p{server.out_fd_, POLLIN, 0};
        if (poll(&p, 1, left_ms) > 0 && !drain(server.out_fd_, server.output_))
            throw std::runtime_error("ameotod exited before listening; it printed:\n" + server.output_);
    }
}

ServerProcess::ServerProcess(ServerProcess&& other) noexcept
    : pid_(other.pid_), out_fd_(other.out_fd_), port_(other.port_), output_(std::move(other.output_)),
      exit_code_(other.exit_code_) {
    other.pid_ = -1;
    other.out_fd_ = -1;
}

std::optional<int> ServerProcess::wait_exit(double timeout_s) {
    if (exit_code_ || pid_ < 0) return exit_code_;
    const auto start = Clock::now();
    do {
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
            exit_code_ = decode_status(status);
            return exit_code_;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    } while (seconds_since(start) < timeout_s);
    return std::nullopt;
}

void ServerProcess::stop() {
    if (pid_ < 0) return;
    if (!exit_code_) {
        kill(pid_, SIGTERM);
        if (!wait_exit(2.0)) {
            kill(pid_, SIGKILL);
            int status = 0;
            waitpid(pid_, &status, 0);
        }
    }
    // Closed only now: ameotod prints "stopped" on its way out, and a closed pipe would SIGPIPE it.
    if (out_fd_ >= 0) close(out_fd_);
    pid_ = -1;
    out_fd_ = -1;
}

ServerProcess::~ServerProcess() { stop(); }

int closed_udp_port() {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    socklen_t size = sizeof a;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size) != 0)
        throw std::runtime_error(std::string("cannot find a free UDP port: ") + std::strerror(errno));
    close(fd);   // the kernel hands out ephemeral ports in turn, so this one stays free for a while
    return ntohs(a.sin_port);
}

}  // namespace ameoto::test
