// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/pipewire/pipewire_server.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "tests/support/timing_scale.hpp"

namespace ameoto::test {
namespace {

using namespace std::chrono_literals;

bool in_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream folders(path ? path : "/usr/bin:/bin");
    for (std::string folder; std::getline(folders, folder, ':');) {
        if (access(((folder.empty() ? "." : folder) + "/" + name).c_str(), X_OK) == 0) return true;
    }
    return false;
}

}  // namespace

std::vector<std::string> PipeWireServer::missing_programs() {
    // Each program with the Debian package it comes in (scripts/install-deps installs them all).
    const std::pair<const char*, const char*> needed[] = {
        {"pipewire", "pipewire-bin"}, {"pw-cli", "pipewire-bin"}, {"pw-metadata", "pipewire-bin"},
        {"pw-jack", "pipewire-jack"}, {"jack_lsp", "jackd2"},       {"jack_connect", "jackd2"},
        {"jack-record", "jack-tools"}};
    std::vector<std::string> missing;
    for (const auto& [program, package] : needed) {
        if (!in_path(program)) missing.push_back(std::string(program) + " (" + package + ")");
    }
    return missing;
}

PipeWireServer::PipeWireServer() {
    std::filesystem::create_directory(runtime_.path() / "config");
    process_ = std::make_unique<ChildProcess>(std::vector<std::string>{"pipewire"}, env(), child_options());
    const auto socket = runtime_.path() / "pipewire-0";
    const auto deadline = std::chrono::steady_clock::now() + scaled(10s);
    while (!std::filesystem::exists(socket)) {
        if (!process_->running() || std::chrono::steady_clock::now() > deadline) {
            throw std::runtime_error("pipewire did not make its socket " + socket.string() + ":\n" + log());
        }
        std::this_thread::sleep_for(20ms);
    }
    run_tool({"pw-metadata", "-n", "settings", "0", "clock.force-rate", std::to_string(kRate)}, "set the rate");
    run_tool({"pw-metadata", "-n", "settings", "0", "clock.force-quantum", std::to_string(kQuantum)}, "set the quantum");
    run_tool({"pw-cli", "create-node", "adapter",
              "{ factory.name=support.null-audio-sink node.name=" + sink() +
                  " media.class=Audio/Sink object.linger=true audio.position=[FL FR] }"},
             "create the null sink");
    run_tool({"pw-cli", "set-param", sink(), "PortConfig",
              "{ direction: Input, mode: dsp, monitor: true, format: { mediaType: audio, mediaSubtype: raw, "
              "format: F32P, rate: " + std::to_string(kRate) + ", channels: 2, position: [ FL, FR ] } }"},
             "give the null sink its ports");
    // The ports appear asynchronously: wait until a JACK client sees the last of them.
    for (;;) {
        const auto ports = run_program(jack_argv({"jack_lsp"}), scaled(10s), env(), child_options());
        if (ports.exit_code == 0 && ports.out.find(sink() + ":monitor_FR") != std::string::npos) break;
        if (std::chrono::steady_clock::now() > deadline) {
            throw std::runtime_error("the null sink's JACK ports did not appear; jack_lsp said:\n" + ports.out + "\npipewire:\n" + log());
        }
        std::this_thread::sleep_for(50ms);
    }
}

PipeWireServer::~PipeWireServer() {
    if (process_) process_->stop(SIGTERM, 5s);
    process_.reset();
    // runtime_ (the socket, its lock, the config folder) goes after the server has ended.
}

std::vector<std::string> PipeWireServer::env(const std::vector<std::string>& more) const {
    const std::string dir = runtime_.path().string();
    std::vector<std::string> e{"XDG_RUNTIME_DIR=" + dir, "PIPEWIRE_RUNTIME_DIR=" + dir, "XDG_CONFIG_HOME=" + dir + "/config"};
    e.insert(e.end(), more.begin(), more.end());
    return e;
}

ChildOptions PipeWireServer::child_options() const {
    ChildOptions o;
    // A desktop's session bus, display and PipeWire or JACK choices must not reach the private server.
    o.unset_env = {"DBUS_SESSION_BUS_ADDRESS", "DISPLAY", "WAYLAND_DISPLAY", "PIPEWIRE_*", "JACK_*"};
    return o;
}

std::vector<std::string> PipeWireServer::jack_argv(std::vector<std::string> argv) const {
    argv.insert(argv.begin(), "pw-jack");
    return argv;
}

std::string PipeWireServer::log() { return process_ ? process_->output() : std::string(); }

void PipeWireServer::run_tool(const std::vector<std::string>& argv, const std::string& what) {
    const auto r = run_program(argv, scaled(10s), env(), child_options());
    if (r.exit_code != 0) {
        throw std::runtime_error("could not " + what + " (" + argv[0] + " exit " + std::to_string(r.exit_code) + "):\n" + r.out +
                                 "\npipewire:\n" + log());
    }
}

}  // namespace ameoto::test
