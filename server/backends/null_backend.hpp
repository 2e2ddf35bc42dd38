#pragma once
// The backend for machines without a JACK server: a thread that calls the same AudioBridge::process
// as JACK would, and writes the stream to a WAV file or discards it.
//
// Interface:
//   NullBackend null(NullBackend::Options{...}, on_finished);   // on_finished: called from the
//                                                                // render thread when --duration ends
//   null.start(bridge); ... null.stop();
//   null.wav()   // the WavWriter, or nullptr when discarding
//
// Pacing: realtime renders each block at its period boundary on the monotonic clock (absolute, so no
// drift); a block that finishes after its boundary counts as an xrun, and the next one waits for the
// following boundary, as a sound card's next period would (realtime_pace.hpp says why). Offline (not
// realtime) renders as fast as the disk takes it: it waits for room in the WAV ring rather than
// dropping, because an offline render must be complete and exact.

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

private:
    void run(AudioBridge& bridge);

    Options options_;
    std::function<void()> on_finished_;
    std::unique_ptr<WavWriter> wav_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> xruns_{0};
    std::thread thread_;
};

}  // namespace ameoto
