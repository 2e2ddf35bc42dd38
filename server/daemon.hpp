// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ameotod's process: choose the audio backend, bind the OSC ports, build the scene, play, serve OSC on
// the control loop until told to stop, then stop in order. daemon.cpp tells it in that order; each
// step's work is in its own file (docs/architecture.md, "Server files").
//
// Interface:
//   Daemon daemon(options);
//   int exit_code = daemon.run();     // returns after SIGINT/SIGTERM, /quit, or the end of --duration;
//                                     // 1 when it could not start (a line on stderr says why)
//
// Start-up order: choose the backend (its sample rate decides the physics' time step), bind the OSC
// ports (a port in use is told at once, not after the scene's seconds of building), build the scene,
// start audio, and only when the first audio block has run tell systemd READY=1. Lines on stdout a
// script can rely on:
//   ameotod: listening on osc.udp://ADDRESS:PORT/
//   ameotod: backend null, writing FILE.wav   |   ameotod: backend jack, client NAME
//   ameotod: running
//   ameotod: stopped
//   ameotod: binaural decoder for blocks of N frames handed to the audio thread   (--format binaural, after
//            the backend's block size changed: tests/integration/binaural_live_test.cpp waits for it)
//
// Thread: run() on the main thread, which becomes the control thread for the loop's lifetime.

#include "server/options.hpp"

namespace ameoto {

class Daemon {
public:
    explicit Daemon(const DaemonOptions& options) : options_(options) {}
    int run();

private:
    DaemonOptions options_;
};

}  // namespace ameoto
