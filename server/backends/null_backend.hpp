// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The backend for machines without a JACK server: a thread that calls the same AudioBridge::process
// as JACK would, and writes the stream to a WAV file or discards it.
//
// Interface:
//   NullBackend null(NullBackend::Options{...}, on_finished);   // on_finished: called from the
//                                                                // render thread when --duration ends
//   null.start(bridge); ... null.stop();
//   null.wav()   // the WavWriter, or nullptr when discarding
//   null.scheduling()   // after start(): how the render thread is scheduled, for the log
//
// Pacing: realtime renders each block at its period boundary on the monotonic clock (absolute, so no
// drift); a block that finishes after its boundary counts as an xrun, and the next one waits for the
// following boundary, as a sound card's next period would (realtime_pace.hpp says why). Offline (not
// realtime) renders as fast as the disk takes it: it waits for room in the WAV ring rather than
// dropping, because an offline render must be complete and exact.
// Clock: paced, each block is timed (BlockTime) by its boundary on the grid, converted to the wall clock
// (wall_offset.hpp), so timetags map to samples without the wake-up jitter; offline, by the wall clock
// when the block is rendered (timetags are then only approximate: use `ameoto render score`).
//
// Scheduling: the render thread is named "ameoto-render" (ps -L, top -H). Paced, it asks for SCHED_FIFO
// at realtime_priority (70 by default), as a JACK client's process thread runs; 0 keeps normal
// scheduling (what jackd's --no-realtime does for its clients). start() sets it from the calling thread, so a refusal (no root and
// no rtprio limit) is reported by scheduling() for the log rather than logged from the render thread;
// the thread then runs at normal priority. Offline renders keep normal scheduling: they are meant to
// take whatever CPU is free, not to preempt the machine.

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "server/backends/backend.hpp"
#include "server/backends/wav_writer.hpp"

namespace ameoto {

class NullBackend : public Backend {
public:
    struct Options {
        double sample_rate = 48000.0;
        int block_size = 256;
        int channels = 2;
        bool realtime = true;
        int realtime_priority = 70;         // SCHED_FIFO priority when realtime, 1..99; 0: normal
        std::optional<double> duration_s;   // stop after this much audio
        std::string output = "-";           // WAV path, or "-" to discard
    };

    NullBackend(const Options& options, std::function<void()> on_finished);
    ~NullBackend() override;

    void start(AudioBridge& bridge) override;
    void stop() override;
    std::uint64_t xruns() const override { return xruns_.load(); }
    std::string name() const override { return "null"; }
    double sample_rate() const override { return options_.sample_rate; }
    int block_size() const override { return options_.block_size; }
    WavWriter* wav() { return wav_.get(); }
    bool realtime() const { return options_.realtime; }
    std::string scheduling() const { return scheduling_; }

private:
    void run(AudioBridge& bridge);

    Options options_;
    std::function<void()> on_finished_;
    std::unique_ptr<WavWriter> wav_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> xruns_{0};
    std::thread thread_;
    std::string scheduling_;   // start()'s outcome, in words
};

}  // namespace ameoto
