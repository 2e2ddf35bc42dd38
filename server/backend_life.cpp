// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backend_life.hpp"

#include <ctime>

#include "server/log_lines.hpp"
#include "server/replies.hpp"

namespace ameoto {
namespace {

std::string default_wav_name() {
    char name[64];
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    std::strftime(name, sizeof name, "ameoto-%Y%m%d-%H%M%S.wav", &local);
    return unused_path(name);
}

}  // namespace

std::unique_ptr<BackendLife> BackendLife::choose(const DaemonOptions& options, SystemdNotifier& systemd,
                                                 std::function<void()> on_finished) {
    std::unique_ptr<BackendLife> life(new BackendLife(systemd));
    if (options.backend != BackendChoice::null) {
        std::string error;
        auto j = JackBackend::open({options.jack_name, options.channels, options.autoconnect, options.start_at_unix_ns.value_or(0),
                                    options.format ? output_channel_names(*options.format) : std::vector<std::string>{}},
                                   error);
        if (j) {
            life->jack_ = j.get();
            life->backend_ = std::move(j);
            return life;
        }
        if (options.backend == BackendChoice::jack) {
            warn("cannot use JACK: " + error);
            return nullptr;
        }
        say(error + ": using the null backend");
    }
    NullBackend::Options n;
    n.sample_rate = options.sample_rate;
    n.block_size = options.block_size;
    n.channels = options.channels;
    n.realtime = options.realtime.value_or(!options.duration_s.has_value());
    n.realtime_priority = options.realtime_priority;
    n.duration_s = options.duration_s;
    n.output = options.output.value_or(default_wav_name());
    try {
        auto nb = std::make_unique<NullBackend>(n, std::move(on_finished));
        life->null_ = nb.get();
        life->backend_ = std::move(nb);
    } catch (const std::exception& e) {
        warn(e.what());
        return nullptr;
    }
    return life;
}

void BackendLife::announce() const {
    if (jack_) say("backend jack, client " + jack_->client_name());
    if (jack_ && jack_->start_gate().start_unix_ns() != 0) say("silent until the --start-at epoch");
    if (null_) say(null_->wav() ? "backend null, writing " + null_->wav()->path() : "backend null, discarding audio");
}

void BackendLife::start(AudioBridge& bridge) {
    backend_->start(bridge);
    if (null_) say("null backend render thread: " + null_->scheduling());
}

void BackendLife::watch(const AudioSnapshot& s, Replies& notices) {
    if (!ready_ && s.callbacks > 0) {
        ready_ = true;
        say("running");
        if (jack_ && jack_->start_gate().start_unix_ns() != 0)
            say("started at the --start-at epoch: its first cycle plays " + std::to_string(jack_->start_gate().lag_ns() / 1000) +
                " us after it");
        systemd_.ready();
        systemd_.status("playing on " + backend_->name());
    }
    if (null_ && null_->wav()) {
        // Disk full, a write error, the file removed: logged and told over OSC; the audio never waits.
        for (std::string error = null_->wav()->take_error(); !error.empty(); error = null_->wav()->take_error()) {
            warn(error);
            notices.notice("output", error);
        }
    }
    if (jack_ && jack_->server_lost()) {
        if (!jack_reported_lost_) {
            warn("the JACK server went away; OSC keeps running, reconnecting when it returns");
            notices.notice("jack", "the JACK server went away; reconnecting when it returns");
            systemd_.status("waiting for the JACK server");
            jack_reported_lost_ = true;
        }
        // Try about every 500 ms (the poll runs every 5 ms).
        if (++reconnect_ticks_ % 100 == 0) {
            std::string error;
            if (jack_->reconnect(error)) {
                say("JACK server is back: playing again");
                notices.notice("jack", "the JACK server is back: playing again");
                systemd_.status("playing on jack");
                jack_reported_lost_ = false;
            } else if (error.find("Hz") != std::string::npos) {
                warn(error);
            }
        }
    }
}

void BackendLife::hangup() {
    if (null_ && null_->wav()) {
        null_->wav()->reopen();
        say("SIGHUP: closed the WAV, continuing in a new file");
    }
}

void BackendLife::report_written() const {
    if (null_ && null_->wav()) say("wrote " + std::to_string(null_->wav()->frames_written()) + " frames to " + null_->wav()->path());
}

}  // namespace ameoto
