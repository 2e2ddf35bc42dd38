// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/take_recording.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "server/log_lines.hpp"
#include "server/scene_manager.hpp"

namespace ameoto {

TakeRecording::~TakeRecording() {
    if (fd_ >= 0) ::close(fd_);
}

bool TakeRecording::open(const DaemonOptions& options) {
    if (!options.record_score) return true;
    if (options.format) format_ = options.format->name();   // so `render score` renders it in the same format
    path_ = *options.record_score;
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        warn("--record-score: cannot write " + path_ + ": " + std::strerror(errno));
        return false;
    }
    return true;
}

bool TakeRecording::begin(const FirstScene& first, AudioBridge& bridge) {
    if (!on()) return true;
    bridge_ = &bridge;
    rate_ = first.config.sample_rate;
    protocol::TakeStart start;
    start.rate_hz = first.config.sample_rate;
    start.channels = first.config.channels;
    start.seed = first.config.seed;
    start.node = first.config.node;
    start.limiter = first.level.limiter;   // the stream's (binaural: on the ears; the renderer's is off)
    start.full_scale_pa = first.config.full_scale_pa;
    start.level_gain_db = first.config.level_gain_db;
    start.adaptive_detail = first.config.adaptive_lod;
    start.scene = format_scene(first.scene);
    start.format = format_;
    append(0, protocol::take_start_address, protocol::take_start_arguments(start));
    write_pending();
    if (write_failed_) return false;
    bridge_->enable_take(queue_records);
    say("recording the take to " + path_ + (start.adaptive_detail ? " (detail may be shed live: it renders again at full detail; "
                                                                     "--fixed-detail for the same samples)"
                                                                   : " (fixed detail: it renders again to the sample)"));
    return true;
}

void TakeRecording::note_load(const void* object, const SceneDescription& scene, const RendererConfig& config) {
    if (!on()) return;
    protocol::TakeSceneChange change;
    change.kind = CommandKind::load_scene;
    change.level_gain_db = config.level_gain_db;
    change.scene = format_scene(scene);
    change.material = config.material;
    change.liquid = config.liquid;
    notes_.emplace(object, std::move(change));
}

void TakeRecording::note_swap(const void* object, CommandKind kind, const RendererConfig& config) {
    if (!on()) return;
    protocol::TakeSceneChange change;
    change.kind = kind;
    change.level_gain_db = config.level_gain_db;
    change.material = config.material;
    change.liquid = config.liquid;
    notes_.emplace(object, std::move(change));
}

void TakeRecording::forget(const void* object) {
    if (const auto found = notes_.find(object); found != notes_.end()) notes_.erase(found);
}

void TakeRecording::append(std::uint64_t frame, const std::string& address, const std::vector<protocol::OscArgument>& args) {
    const std::vector<unsigned char> element = protocol::take_element(frame, rate_, address, args);
    pending_.insert(pending_.end(), element.begin(), element.end());
}

void TakeRecording::write_pending() {
    std::size_t at = 0;
    while (at < pending_.size()) {
        const ssize_t n = ::write(fd_, pending_.data() + at, pending_.size() - at);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            // A full disk or an I/O error: the take stops being the stream. Said once; the audio goes on.
            if (!write_failed_) warn("--record-score: cannot write " + path_ + ": " + std::strerror(errno) + "; the take ends here");
            write_failed_ = true;
            break;
        }
        at += static_cast<std::size_t>(n);
    }
    pending_.clear();
}

void TakeRecording::drain() {
    if (!on() || !bridge_ || write_failed_) return;
    // frames first: every command applied before it is already in the queue (audio_bridge.cpp).
    const std::uint64_t frames = bridge_->snapshot().frames;
    AppliedCommand applied;
    while (bridge_->take()->try_pop(applied)) {
        const Command& c = applied.command;
        if (c.kind == CommandKind::load_scene || c.kind == CommandKind::swap_surface || c.kind == CommandKind::swap_liquid) {
            const auto found = notes_.find(c.object);
            if (found == notes_.end()) continue;   // not noted: cannot happen (the scene manager notes every send)
            protocol::TakeSceneChange change = std::move(found->second);
            notes_.erase(found);
            change.frame = applied.frame;
            append(applied.frame, protocol::take_scene_address, protocol::take_scene_arguments(change));
            ++scenes_;
        } else {
            append(applied.frame, protocol::take_command_address, protocol::take_command_arguments(applied.frame, c));
            ++commands_;
        }
    }
    if (frames > frames_written_ || !pending_.empty()) {
        append(frames, protocol::take_frames_address, protocol::take_frames_arguments(frames, bridge_->take_lost()));
        frames_written_ = frames;
    }
    if (!pending_.empty()) write_pending();
}

void TakeRecording::finish() {
    if (!on() || !bridge_) return;
    drain();
    if (!write_failed_) {
        const std::uint64_t frames = bridge_->snapshot().frames;
        append(frames, protocol::take_end_address, protocol::take_frames_arguments(frames, bridge_->take_lost()));
        write_pending();
    }
    ::close(fd_);
    fd_ = -1;
    std::string line = "take: " + std::to_string(commands_) + (commands_ == 1 ? " command and " : " commands and ") +
                       std::to_string(scenes_) + (scenes_ == 1 ? " scene change in " : " scene changes in ") +
                       path_ + " (" + std::to_string(frames_written_) + " frames)";
    if (bridge_->take_lost() > 0) line += "; " + std::to_string(bridge_->take_lost()) + " commands lost (the queue was full): it is not the stream";
    say(line);
}

}  // namespace ameoto
