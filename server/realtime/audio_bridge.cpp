// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/realtime/audio_bridge.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "server/realtime/rt_probe.hpp"

namespace ameoto {
namespace {
std::int64_t now_ns(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}
}  // namespace

AudioBridge::AudioBridge(std::unique_ptr<Renderer> renderer, std::size_t queue_capacity, std::unique_ptr<BinauralStage> binaural)
    : renderer_(std::move(renderer)),
      sample_rate_(renderer_->config().sample_rate),
      channels_(binaural ? 2 : renderer_->config().channels),
      commands_(queue_capacity),
      events_(queue_capacity),
      meter_(sample_rate_, channels_),
      loudness_(channels_, sample_rate_) {
    output_gain_db_.store(renderer_->level_gain_db() + renderer_->output().gain_db());
    if (binaural) {
        if (binaural->bus_channels() != renderer_->config().channels)
            throw std::invalid_argument("the binaural stage decodes " + std::to_string(binaural->bus_channels()) +
                                        " channels but the renderer makes " + std::to_string(renderer_->config().channels));
        binaural_block_.store(binaural->block_frames());
        binaural_ = binaural.release();
    }
}

bool AudioBridge::offer_binaural(std::unique_ptr<BinauralStage>& stage) {
    // binaural_ itself is the audio thread's; channels_ is fixed at construction (2 when binaural).
    if (!stage || binaural_block() == 0 || stage->bus_channels() != renderer_->config().channels) return false;
    if (!binaural_in_.try_push(stage.get())) return false;
    (void)stage.release();   // the audio thread owns it now
    return true;
}

std::unique_ptr<BinauralStage> AudioBridge::take_retired_binaural() {
    BinauralStage* old = nullptr;
    return binaural_out_.try_pop(old) ? std::unique_ptr<BinauralStage>(old) : nullptr;
}

double AudioBridge::take_cpu_peak_percent() { return 100.0 * load_peak_.exchange(0.0, std::memory_order_relaxed); }

AudioBridge::~AudioBridge() {
    // Audio has stopped (the backend is stopped before the bridge goes). Objects still travelling in
    // either queue are freed here; the renderer frees what it holds.
    Command command;
    while (commands_.try_pop(command)) {
        if (command.kind == CommandKind::swap_surface || command.kind == CommandKind::swap_liquid)
            delete static_cast<UmbrellaScene*>(command.object);
        else if (command.kind == CommandKind::load_scene)
            delete static_cast<LoadedScene*>(command.object);
        else if (command.kind == CommandKind::orientation)
            delete static_cast<AmbixRotation*>(command.object);
    }
    for (BinauralStage* stage = nullptr; binaural_in_.try_pop(stage);) delete stage;
    for (BinauralStage* stage = nullptr; binaural_out_.try_pop(stage);) delete stage;
    delete binaural_;
    RendererEvent event;
    while (events_.try_pop(event)) {
        if (event.kind != RendererEventKind::retired) continue;
        if (event.object_type == RetiredObject::scene_surfaces) delete static_cast<SceneSurfaces*>(event.object);
        else if (event.object_type == RetiredObject::loaded_scene) delete static_cast<LoadedScene*>(event.object);
        else if (event.object_type == RetiredObject::rotation) delete static_cast<AmbixRotation*>(event.object);
        else delete static_cast<UmbrellaScene*>(event.object);
    }
}

AudioSnapshot AudioBridge::snapshot() const {
    AudioSnapshot s;
    s.cpu_average_percent = 100.0 * load_average_.load(std::memory_order_relaxed);
    s.cpu_peak_percent = 100.0 * load_peak_.load(std::memory_order_relaxed);
    s.frames = frames_.load(std::memory_order_acquire);
    s.drops = drops_.load(std::memory_order_relaxed);
    s.late_commands = late_.load(std::memory_order_relaxed);
    s.busy_commands = busy_.load(std::memory_order_relaxed);
    s.body_resets = resets_.load(std::memory_order_relaxed);
    s.events_lost = events_lost_.load(std::memory_order_relaxed);
    s.callbacks = callbacks_.load(std::memory_order_relaxed);
    s.active_impacts = active_impacts_.load(std::memory_order_relaxed);
    s.active_full_drops = active_full_drops_.load(std::memory_order_relaxed);
    s.active_grains = active_grains_.load(std::memory_order_relaxed);
    s.rain_rate_mm_per_h = rain_rate_.load(std::memory_order_relaxed);
    s.clock_ppm = (clock_rate_ratio_.load(std::memory_order_relaxed) - 1.0) * 1e6;
    s.clipped_samples = clipped_.load(std::memory_order_relaxed);
    s.output_gain_db = output_gain_db_.load(std::memory_order_relaxed);
    return s;
}

AudioClock AudioBridge::clock() const {
    std::uint64_t seq, frame;
    std::int64_t unix_ns;
    double ratio;
    do {   // sequence lock: retry while the audio thread is mid-update (odd) or updated meanwhile
        seq = clock_sequence_.load(std::memory_order_acquire);
        frame = clock_frame_.load(std::memory_order_relaxed);
        unix_ns = clock_unix_ns_.load(std::memory_order_relaxed);
        ratio = clock_rate_ratio_.load(std::memory_order_relaxed);
        std::atomic_thread_fence(std::memory_order_acquire);
    } while ((seq & 1) || seq != clock_sequence_.load(std::memory_order_relaxed));
    return AudioClock{seq != 0, frame, unix_ns, sample_rate_ * ratio};
}

std::uint64_t frame_at(const AudioClock& clock, double unix_seconds) {
    if (!clock.valid) return 0;
    const double offset = std::round((unix_seconds - static_cast<double>(clock.unix_ns) * 1e-9) * clock.sample_rate);
    const double target = static_cast<double>(clock.frame) + offset;
    return target <= 0.0 ? 0 : static_cast<std::uint64_t>(target);
}

void AudioBridge::process(int frames, float* const* outputs, const BlockTime& time) {
    rt::Scope audited;
    BlockTrace::Reading thread_before;
    if (trace_) thread_before = BlockTrace::read_thread();
    const std::int64_t start = now_ns(CLOCK_MONOTONIC);
    const std::uint64_t first_frame = renderer_->frame();

    const std::uint64_t seq = clock_sequence_.load(std::memory_order_relaxed);
    clock_sequence_.store(seq + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    clock_frame_.store(renderer_->frame(), std::memory_order_relaxed);
    clock_unix_ns_.store(time.valid ? time.unix_ns : now_ns(CLOCK_REALTIME), std::memory_order_relaxed);
    clock_rate_ratio_.store(time.valid ? time.rate_ratio : 1.0, std::memory_order_relaxed);
    clock_sequence_.store(seq + 2, std::memory_order_release);

    Command command;
    while (commands_.try_pop(command)) {
        const std::uint64_t busy_before = renderer_->stats().busy_commands;
        renderer_->schedule(command);
        // --record-score: what the renderer accepted, at the sample it applies it (Renderer::schedule: an
        // untimed or late command at the block's first sample). Written before frames_ is published, so a
        // reader that saw frames_ reach F has every command applied before F.
        if (take_ && command.kind != CommandKind::sync && renderer_->stats().busy_commands == busy_before) {
            const std::uint64_t at = command.timed ? std::max(command.frame, first_frame) : first_frame;
            if (!take_->try_push(AppliedCommand{at, command})) take_lost_.fetch_add(1, std::memory_order_relaxed);
        }
    }
    if (binaural_) {
        // A stage for a new block size, when the control thread has built one; the old one goes back to be
        // freed (taken only when the return queue has room, so no stage is ever lost).
        BinauralStage* next = nullptr;
        while (binaural_out_.size_approx() < binaural_out_.capacity() && binaural_in_.try_pop(next)) {
            (void)binaural_out_.try_push(binaural_);
            binaural_ = next;
            binaural_block_.store(next->block_frames(), std::memory_order_relaxed);
        }
        const int block = binaural_->block_frames();
        if (frames != block) binaural_unmatched_.fetch_add(1, std::memory_order_relaxed);
        if (frames <= block) {
            renderer_->process(frames, binaural_->bus());
            ear_clipped_ += static_cast<std::uint64_t>(binaural_->decode(frames, outputs[0], outputs[1]));
        } else {
            for (int done = 0; done < frames; done += block) renderer_->process(std::min(block, frames - done), binaural_->bus());
            std::fill(outputs[0], outputs[0] + frames, 0.0f);
            std::fill(outputs[1], outputs[1] + frames, 0.0f);
        }
    } else {
        renderer_->process(frames, outputs);
    }
    meter_.measure(frames, outputs, renderer_->frame());
    loudness_.feed(frames, outputs);
    // Take an event from the renderer only when the queue has room for it: events that hand back an
    // object (a retired canopy) must never be dropped; the rest wait in the renderer's own list.
    RendererEvent event;
    while (events_.size_approx() < events_.capacity() && renderer_->poll_event(event))
        if (!events_.try_push(event)) events_lost_.fetch_add(1, std::memory_order_relaxed);

    const RendererStats& st = renderer_->stats();
    drops_.store(st.drops + st.surface_drops, std::memory_order_relaxed);   // every surface's
    late_.store(st.late_commands, std::memory_order_relaxed);
    busy_.store(st.busy_commands, std::memory_order_relaxed);
    resets_.store(st.body_resets, std::memory_order_relaxed);
    active_impacts_.store(st.active_impacts, std::memory_order_relaxed);
    active_full_drops_.store(st.active_full_drops, std::memory_order_relaxed);
    active_grains_.store(st.active_grains, std::memory_order_relaxed);
    rain_rate_.store(st.rain_rate_mm_per_h, std::memory_order_relaxed);
    // Binaural: the ears' samples past full scale (what leaves), not the bus's (not limited there).
    clipped_.store(binaural_ ? ear_clipped_ : st.clipped_samples, std::memory_order_relaxed);
    output_gain_db_.store(renderer_->level_gain_db() + renderer_->output().gain_db(), std::memory_order_relaxed);
    const std::uint64_t callback = callbacks_.fetch_add(1, std::memory_order_relaxed);
    frames_.store(renderer_->frame(), std::memory_order_release);

    const double period = frames / sample_rate_;
    const std::int64_t wall_ns = now_ns(CLOCK_MONOTONIC) - start;
    const double load = static_cast<double>(wall_ns) * 1e-9 / period;
    if (trace_)
        trace_->record(callback, first_frame, frames, start, wall_ns, thread_before, BlockTrace::read_thread(),
                       renderer_->last_block());
    // Exponential mean with a time constant of about one second of audio.
    const double alpha = std::min(1.0, period / 1.0);
    load_average_.store(load_average_.load(std::memory_order_relaxed) * (1.0 - alpha) + load * alpha,
                        std::memory_order_relaxed);
    if (load > load_peak_.load(std::memory_order_relaxed)) load_peak_.store(load, std::memory_order_relaxed);
    renderer_->set_measured_load(load);   // the governor's input for the next block (live scenes only)
}

}  // namespace ameoto
