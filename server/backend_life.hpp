// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The audio backend's life: which one runs (JACK when a server runs, else the null backend writing a
// WAV), its start, its health while it plays (the first block, WAV write errors, a JACK server that
// goes away and comes back), SIGHUP's new WAV, its stop, and the lines the log and systemd get about it.
//
// Interface:
//   auto life = BackendLife::choose(options, systemd, [&] { loop.shutdown_soon(); });   // nullptr: refused, said why
//   life->backend()           // its sample rate decides the physics' time step
//   life->live()              // paced to a clock (JACK, or the null backend with --realtime)
//   life->announce();         // "backend jack, client NAME" | "backend null, writing FILE" | "..., discarding audio"
//   life->start(bridge);      // audio runs from here
//   life->watch(snapshot, notices);   // every poll: READY=1 after the first block; faults told as /notice
//   life->hangup();           // SIGHUP: the null backend's WAV closed, continued in a new file
//   life->stop();             // the audio thread will not call the bridge again
//   life->report_written();   // "wrote N frames to FILE"
//
// Threads: all on the control thread. The null backend calls on_finished from its render thread (at
// the end of --duration), so that must only post. backend()'s name(), sample_rate(), block_size() and
// xruns() are also read from the TCP thread for /status (constants and atomics).

#include <functional>
#include <memory>
#include <string>

#include "server/backends/backend.hpp"
#include "server/backends/jack_backend.hpp"
#include "server/backends/null_backend.hpp"
#include "server/options.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/systemd_notify.hpp"

namespace ameoto {

class Replies;

class BackendLife {
public:
    static std::unique_ptr<BackendLife> choose(const DaemonOptions& options, SystemdNotifier& systemd,
                                               std::function<void()> on_finished);

    Backend& backend() const { return *backend_; }
    bool live() const { return !null_ || null_->realtime(); }
    void announce() const;
    void start(AudioBridge& bridge);
    void watch(const AudioSnapshot& s, Replies& notices);
    void hangup();
    void stop() { backend_->stop(); }
    void report_written() const;
    void set_wav_comment(const std::string& text) {   // the null backend's WAV: the calibration (before start)
        if (null_ && null_->wav()) null_->wav()->set_comment(text);
    }

private:
    explicit BackendLife(SystemdNotifier& systemd) : systemd_(systemd) {}

    SystemdNotifier& systemd_;
    std::unique_ptr<Backend> backend_;
    JackBackend* jack_ = nullptr;   // the same object as backend_, when it is JACK
    NullBackend* null_ = nullptr;   // or when it is the null backend
    bool ready_ = false;            // the first block has run: READY=1 sent
    bool jack_reported_lost_ = false;
    std::uint64_t reconnect_ticks_ = 0;
};

}  // namespace ameoto
