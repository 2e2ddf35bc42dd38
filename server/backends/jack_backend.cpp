// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/jack_backend.hpp"

#include <jack/metadata.h>

#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <cstdio>

#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/rt_probe.hpp"
#include "server/realtime/wall_offset.hpp"

namespace ameoto {

namespace {
// libjack reports every failed connection attempt on stderr (five lines each time): when ameotod looks
// for a server at start-up (--backend auto finds none on most machines) and every 500 ms while the
// server is away. Those lines are silenced while connecting; ameotod says in one line what happened.
// Once connected, libjack's messages are shown, prefixed.
std::atomic<bool> quiet_jack{false};
void jack_message(const char* text) {
    if (!quiet_jack.load()) std::fprintf(stderr, "ameotod: jack: %s\n", text);
}
}  // namespace

std::unique_ptr<JackBackend> JackBackend::open(const Options& options, std::string& error) {
    std::unique_ptr<JackBackend> backend(new JackBackend(options));
    quiet_jack.store(true);
    const bool ok = backend->open_client(error);
    quiet_jack.store(false);
    return ok ? std::move(backend) : nullptr;
}

JackBackend::~JackBackend() { stop(); }

bool JackBackend::open_client(std::string& error) {
    jack_set_error_function(&jack_message);
    jack_set_info_function(&jack_message);
    jack_status_t status{};
    client_ = jack_client_open(options_.client_name.c_str(), JackNoStartServer, &status);
    if (!client_) {
        error = (status & JackServerFailed) ? "no JACK server is running" : "jack_client_open failed (status 0x" +
                                                                                std::to_string(static_cast<int>(status)) + ")";
        return false;
    }
    const double rate = jack_get_sample_rate(client_);
    if (sample_rate_ != 0.0 && rate != sample_rate_) {
        error = "the JACK server runs at " + std::to_string(static_cast<int>(rate)) + " Hz but the scene was built for " +
                std::to_string(static_cast<int>(sample_rate_)) + " Hz; restart ameotod";
        close_client();
        return false;
    }
    sample_rate_ = rate;
    cycle_clock_ = CycleClock(rate);   // the callback is not registered yet: no audio thread reads it
    block_size_.store(static_cast<int>(jack_get_buffer_size(client_)));
    ports_.clear();
    for (int c = 0; c < options_.channels; ++c) {
        const std::string port_name = "out_" + std::to_string(c + 1);
        jack_port_t* port = jack_port_register(client_, port_name.c_str(), JACK_DEFAULT_AUDIO_TYPE, JackPortIsOutput, 0);
        if (!port) {
            error = "cannot register JACK port " + port_name;
            close_client();
            return false;
        }
        ports_.push_back(port);
        // What the port carries, for patchbays that show pretty names (JACK metadata API, JACK 1.9.13+).
        // A server without metadata support still plays: the label is a courtesy, said once if refused.
        if (static_cast<std::size_t>(c) < options_.port_labels.size()) {
            const jack_uuid_t uuid = jack_port_uuid(port);
            if (jack_set_property(client_, uuid, JACK_METADATA_PRETTY_NAME, options_.port_labels[static_cast<std::size_t>(c)].c_str(),
                                  "text/plain") != 0 &&
                c == 0)
                std::fprintf(stderr, "ameotod: the JACK server did not take the ports' pretty names (metadata)\n");
        }
    }
    buffers_.assign(ports_.size(), nullptr);
    jack_set_process_callback(client_, &JackBackend::on_process, this);
    jack_set_xrun_callback(client_, &JackBackend::on_xrun, this);
    jack_set_buffer_size_callback(client_, &JackBackend::on_buffer_size, this);
    jack_on_info_shutdown(client_, &JackBackend::on_shutdown, this);
    lost_.store(false);
    return true;
}

void JackBackend::close_client() {
    if (client_) {
        jack_client_close(client_);
        client_ = nullptr;
    }
}

bool JackBackend::activate(std::string& error) {
    if (jack_activate(client_) != 0) {
        error = "cannot activate the JACK client";
        return false;
    }
    if (options_.autoconnect) {
        const char** playback = jack_get_ports(client_, nullptr, JACK_DEFAULT_AUDIO_TYPE, JackPortIsPhysical | JackPortIsInput);
        for (std::size_t c = 0; playback && playback[c] && c < ports_.size(); ++c)
            jack_connect(client_, jack_port_name(ports_[c]), playback[c]);
        if (playback) jack_free(playback);
    }
    return true;
}

void JackBackend::start(AudioBridge& bridge) {
    bridge_ = &bridge;
    std::string error;
    if (!activate(error)) std::fprintf(stderr, "ameotod: %s\n", error.c_str());
}

void JackBackend::stop() {
    if (client_ && !lost_.load()) jack_deactivate(client_);
    close_client();
}

bool JackBackend::reconnect(std::string& error) {
    quiet_jack.store(true);
    close_client();   // the dead client: JACK allows closing it from a non-JACK thread after shutdown
    const bool ok = open_client(error) && activate(error);
    quiet_jack.store(false);
    return ok;
}

std::string JackBackend::client_name() const { return client_ ? jack_get_client_name(client_) : options_.client_name; }

int JackBackend::on_process(jack_nframes_t frames, void* self) {
    // libjack (jackd2) stops this thread with pthread_cancel, and sets its cancel type to asynchronous
    // (JackPosixThread::ThreadHandler): a deactivation (ameotod stopping, or closing a client whose
    // server died, before a new client takes over the same renderer) could otherwise unwind through the
    // renderer at any instruction and leave it half-stepped. Held off for the block, the cancellation
    // acts when it is re-enabled below, where no frame of ours has anything to unwind. Found under ASan,
    // whose unwinding hook aborted inside the renderer when jack_test stopped ameotod. The state change is
    // a flag in the thread's own descriptor: no syscall, no lock, no allocation.
    const std::int64_t callback_ns = clock_ns(CLOCK_MONOTONIC);   // first: the envelope wants the earliest reading
    int previous = PTHREAD_CANCEL_ENABLE;
    pthread_setcancelstate(PTHREAD_CANCEL_DISABLE, &previous);
    auto* me = static_cast<JackBackend*>(self);
    for (std::size_t c = 0; c < me->ports_.size(); ++c)
        me->buffers_[c] = static_cast<float*>(jack_port_get_buffer(me->ports_[c], frames));
    // The block's wall time: the lower envelope of the callback's own readings (server/backends/
    // cycle_clock.hpp says why not JACK's filtered cycle times); JACK's filtered period gives the rate.
    // Every call here reads JACK's shared memory or the vDSO clocks: no syscall.
    CycleReading reading;
    reading.callback_mono_ns = callback_ns;
    reading.frames = frames;
    reading.jack_frame = jack_last_frame_time(me->client_);
    jack_nframes_t cycle_frames = 0;
    jack_time_t cycle_usecs = 0, next_usecs = 0;
    const bool have_cycle = jack_get_cycle_times(me->client_, &cycle_frames, &cycle_usecs, &next_usecs, &reading.period_usecs) == 0;
    if (!have_cycle) reading.period_usecs = 0.0f;
    reading.wall_minus_mono_ns = realtime_minus_monotonic_ns();
    const std::uint64_t xruns = me->xruns_.load(std::memory_order_relaxed);
    reading.xrun = xruns != me->xruns_seen_;
    me->xruns_seen_ = xruns;
    const BlockTime time = me->cycle_clock_.block(reading);
    // The start gate decides by JACK's own filtered cycle time, not by this client's envelope: every client
    // of one server reads the same value from JACK's shared memory, so all nodes there open on the same
    // cycle (their envelopes differ by their wake-up order, tens of microseconds). jackd2 and PipeWire's
    // libjack count that time as CLOCK_MONOTONIC in microseconds.
    const std::int64_t cycle_ns =
        have_cycle ? static_cast<std::int64_t>(cycle_usecs) * 1000 + reading.wall_minus_mono_ns : time.unix_ns;
    const auto period_ns = static_cast<std::int64_t>(1e9 * frames / me->sample_rate_);
    if (me->start_gate_.open(cycle_ns, period_ns)) {
        me->bridge_->process(static_cast<int>(frames), me->buffers_.data(), time);
    } else {
        rt::Scope audited;   // (the bridge audits its own process(): these cycles are the gate's alone)
        for (float* b : me->buffers_) std::fill(b, b + frames, 0.0f);   // before the epoch: silence, the renderer waits
    }
    pthread_setcancelstate(previous, nullptr);
    return 0;
}

int JackBackend::on_xrun(void* self) {
    static_cast<JackBackend*>(self)->xruns_.fetch_add(1);
    return 0;
}

int JackBackend::on_buffer_size(jack_nframes_t frames, void* self) {
    static_cast<JackBackend*>(self)->block_size_.store(static_cast<int>(frames));
    return 0;
}

void JackBackend::on_shutdown(jack_status_t, const char*, void* self) { static_cast<JackBackend*>(self)->lost_.store(true); }

}  // namespace ameoto
