// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The JACK backend: ports <name>:out_1..N (with metadata pretty names saying what each carries), the
// process callback calls AudioBridge::process.
//
// Interface:
//   std::string error;
//   auto jack = JackBackend::open(JackBackend::Options{...}, error);   // nullptr + error when no server
//   jack->start(bridge);             // registers callbacks, activates, connects to system playback if asked
//   control thread, on a timer:
//     if (jack->server_lost()) jack->reconnect(error);   // true once playing again
//   jack->stop();
//
// The client never starts a server (JackNoStartServer). When the server goes away JACK calls the
// info-shutdown callback (from one of its threads); that only sets a flag. The control thread then
// closes the dead client and tries to open a new one until the server is back, and resumes with the
// same bridge, so the scene, the rain and the sample clock carry on. A returning server at another
// sample rate is refused with a message: the physics was built for the first rate.
// Clock: each block is timed by JACK's own delay-locked loop (jack_get_cycle_times, cycle_clock.hpp), so
// timetags of separate packets keep their distances to the sample; a new client starts a new loop.
// Start (--start-at, start_gate.hpp): until the epoch each cycle is silence and the renderer does not
// run, so nodes of one scene on one server begin their rain at the same frame.

#include <jack/jack.h>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "server/backends/backend.hpp"
#include "server/backends/cycle_clock.hpp"
#include "server/backends/start_gate.hpp"

namespace ameoto {

class JackBackend : public Backend {
public:
    struct Options {
        std::string client_name = "ameoto";
        int channels = 2;
        bool autoconnect = false;
        std::int64_t start_unix_ns = 0;   // --start-at: silence until this wall time (start_gate.hpp); 0: none
        // Each port's JACK metadata pretty name (JACK_METADATA_PRETTY_NAME: "ACN 0 W", "left", ...): the
        // ports keep the names out_1..N that patches connect by; empty: no metadata.
        std::vector<std::string> port_labels;
    };

    static std::unique_ptr<JackBackend> open(const Options& options, std::string& error);
    ~JackBackend() override;

    void start(AudioBridge& bridge) override;
    void stop() override;
    std::uint64_t xruns() const override { return xruns_.load(); }
    std::string name() const override { return "jack"; }
    double sample_rate() const override { return sample_rate_; }
    int block_size() const override { return block_size_.load(); }

    bool server_lost() const { return lost_.load(); }
    bool reconnect(std::string& error);
    std::string client_name() const;
    const StartGate& start_gate() const { return start_gate_; }

private:
    explicit JackBackend(const Options& options) : options_(options), start_gate_(options.start_unix_ns) {}
    bool open_client(std::string& error);
    void close_client();
    bool activate(std::string& error);

    static int on_process(jack_nframes_t frames, void* self);
    static int on_xrun(void* self);
    static int on_buffer_size(jack_nframes_t frames, void* self);
    static void on_shutdown(jack_status_t code, const char* reason, void* self);

    Options options_;
    jack_client_t* client_ = nullptr;
    std::vector<jack_port_t*> ports_;
    std::vector<float*> buffers_;     // sized once; filled in each cycle without allocation
    AudioBridge* bridge_ = nullptr;
    double sample_rate_ = 0.0;
    std::atomic<int> block_size_{0};
    std::atomic<std::uint64_t> xruns_{0};
    std::atomic<bool> lost_{false};
    CycleClock cycle_clock_{48000.0};   // the audio thread's; set for the server's rate in open_client
    std::uint64_t xruns_seen_ = 0;      // the audio thread's: xruns_ when it last looked
    StartGate start_gate_;              // the audio thread's; kept across a reconnection (one epoch a run)
};

}  // namespace ameoto
