#pragma once
// ameotod's control thread: one Boost.Asio io_context that serves OSC, signals and timers, and
// drives the audio backend through the AudioBridge.
//
// Interface:
//   Daemon daemon(options);
//   int exit_code = daemon.run();     // returns after SIGINT/SIGTERM, /quit, or the end of --duration
//
// Start-up order: choose the backend (its sample rate decides the physics' time step), build the
// scene, bind the OSC port, start audio, and only when the first audio block has run tell systemd
// READY=1. Lines on stdout a script can rely on:
//   ameotod: listening on osc.udp://ADDRESS:PORT/
//   ameotod: backend null, writing FILE.wav   |   ameotod: backend jack, client NAME
//   ameotod: running
//   ameotod: stopped

#include <memory>

#include "server/options.hpp"

namespace ameoto {

class Daemon {
public:
    explicit Daemon(const DaemonOptions& options);
    ~Daemon();
    int run();

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace ameoto
