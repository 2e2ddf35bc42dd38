// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/jack_server.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace ameoto::test {
namespace {

std::atomic<int> counter{0};

bool other_jackd_running() {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
        std::ifstream comm(entry.path() / "comm");
        std::string name;
        if (comm >> name && name == "jackd") return true;
    }
    return false;
}

}  // namespace

JackServer::JackServer(bool realtime)
    : name_("ameoto-test-" + std::to_string(getpid()) + "-" + std::to_string(counter++)), realtime_(realtime) {
    start();
}

JackServer::~JackServer() {
    stop();
    // jackd leaves semaphores and shared memory in /dev/shm: those named after this server always go;
    // the ones all JACK servers of this user share (jack-shm-registry, jack-UID-N, jack_db-UID) go only
    // when no other jackd runs, so a user's own JACK server is never disturbed.
    const bool alone = !other_jackd_running();
    const std::string uid = std::to_string(getuid());
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/dev/shm", ec)) {
        const std::string f = entry.path().filename().string();
        const bool ours = f.find(name_) != std::string::npos;
        const bool shared = f == "jack-shm-registry" || f.rfind("jack-" + uid + "-", 0) == 0 || f == "jack_db-" + uid;
        if (ours || (alone && shared)) std::filesystem::remove(entry.path(), ec);
    }
}

void JackServer::start() {
    using namespace std::chrono_literals;
    // --no-realtime goes before -d: it is a server option, not a driver option.
    std::vector<std::string> argv{"/usr/bin/jackd", realtime_ ? "--realtime" : "--no-realtime", "-n", name_, "-d", "dummy", "-r", "48000", "-p", "256"};
    process_ = std::make_unique<ChildProcess>(argv);
    ChildProcess wait({"/usr/bin/jack_wait", "-w", "-t", "10"}, env());
    if (wait.wait(15s) != 0) throw std::runtime_error("jackd did not come up:\n" + process_->output());
}

void JackServer::stop() {
    using namespace std::chrono_literals;
    if (process_) process_->stop(SIGTERM, 5s);
    process_.reset();
}

void JackServer::kill() {
    using namespace std::chrono_literals;
    if (process_) process_->stop(SIGKILL, 5s);
    process_.reset();
}

const std::string& JackServer::output() {
    static const std::string none;
    return process_ ? process_->output() : none;
}

std::vector<std::string> JackServer::env(const std::vector<std::string>& more) const {
    std::vector<std::string> e{"JACK_DEFAULT_SERVER=" + name_, "JACK_NO_AUDIO_RESERVATION=1"};
    e.insert(e.end(), more.begin(), more.end());
    return e;
}

}  // namespace ameoto::test
