// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The boundary between the control thread and the audio thread. Both backends call process() from
// their audio thread; the control thread talks to it only through two fixed-size lock-free queues
// and a handful of atomics.
//
// Interface:
//   AudioBridge bridge(std::make_unique<Renderer>(config), 4096);   // control thread, allocates
//   AudioBridge bridge(renderer, 4096, std::move(stage));   // --format binaural: the renderer's AmbiX bus
//                                                           // decoded to two ears (binaural_stage.hpp)
//   control thread:  bridge.send(command)  -> false when the queue is full (answer /fail busy)
//                    bridge.poll_event(e)  -> replies decided on the audio thread (/synced, busy)
//                    bridge.snapshot()     -> counters and load for /status (reads only)
//                    bridge.take_cpu_peak_percent() -> peak load since the last call (one reader: /status)
//                    bridge.frame_for(unix_seconds) -> the sample a timetag falls on
//                    bridge.clock() + frame_at(clock, unix_seconds) -> the same, one clock reading for a whole packet
//                    bridge.take_meter(w)  -> the next finished level-meter window (/meter)
//                    bridge.loudness_tap() -> the output's samples for /meter's loudness (loudness_tap.hpp)
//                    bridge.enable_block_trace(n) -> before audio starts: record every block (block_trace.hpp)
//                    bridge.block_trace()  -> that record's ring (null when off), read by one thread
//                    bridge.enable_take(n)  -> before audio starts: record every command applied (--record-score)
//                    bridge.take()         -> that record's queue (null when off), read by one thread
//                    bridge.take_lost()    -> commands applied that found the queue full (the take is incomplete)
//                    bridge.offer_binaural(stage) -> binaural: a stage for a new block size (JACK's buffer size
//                                           changed), swapped in at the next block; false: the queue is full
//                    bridge.take_retired_binaural() -> the stage it replaced, to be freed here (null: none yet)
//                    bridge.binaural_block()  -> the block size of the stage playing (0: not binaural)
//                    bridge.binaural_unmatched_blocks() -> blocks of another size than the stage's (silence
//                                           or padded, binaural_stage.hpp)
//   audio thread:    bridge.process(frames, outputs, time)   // never allocates, frees, locks, blocks or logs
//                    time: the backend's filtered clock for this block (BlockTime), or {} for none
//
// Binaural: the renderer writes its (N+1)^2-channel bus into the stage's own preallocated bus, and the
// stage decodes it into outputs[0] and outputs[1]; the meter, the loudness tap and channels() are the two
// ears'. A block longer than the stage's (JACK's buffer grew, the new stage not yet here) is rendered in
// pieces of the stage's size into its bus, so the scene's time runs on, and plays silence.
//
// Load: each process() measures its own duration with the monotonic clock (a vDSO read, no system
// call) against the block's period; the average is an exponential mean over about one second, the
// peak is the maximum since the last take_cpu_peak_percent().
// Clock: each process() publishes (frame, wall time, rate) through a sequence lock so the control thread
// can turn a bundle's timetag into a sample time without stopping the audio thread. The wall time is
// the backend's filtered estimate of when the block's first frame plays (BlockTime), not a reading
// taken when the callback happens to run: that reading jitters by the thread's wake-up latency (tens
// to hundreds of microseconds, i.e. several samples), so bundles sent in separate packets landed a few
// samples off their distance (issue 22: 48 006 and 48 008 samples for 1.000 s at 48 kHz). With JACK the
// estimate is the lower envelope of the callback's readings (backends/cycle_clock.hpp); on the paced null backend, its grid of
// period deadlines. Without one (the offline null backend), the callback's own reading is used.

#include <atomic>
#include <cstdint>
#include <memory>
#include <type_traits>

#include "engine/render/renderer.hpp"
#include "server/realtime/binaural_stage.hpp"
#include "server/realtime/block_trace.hpp"
#include "server/realtime/level_meter.hpp"
#include "server/realtime/loudness_tap.hpp"
#include "server/realtime/spsc_queue.hpp"

namespace ameoto {

struct AudioSnapshot {
    double cpu_average_percent = 0.0;
    double cpu_peak_percent = 0.0;    // since the last take_cpu_peak_percent()
    std::uint64_t frames = 0;
    std::uint64_t drops = 0;
    std::uint64_t late_commands = 0;
    std::uint64_t busy_commands = 0;
    std::uint64_t body_resets = 0;
    std::uint64_t events_lost = 0;
    std::uint64_t callbacks = 0;
    int active_impacts = 0;       // impulse-model impacts sounding
    int active_full_drops = 0;    // lattice drops in the scene
    int active_grains = 0;        // texture grains sounding
    double rain_rate_mm_per_h = 0.0;
    double clock_ppm = 0.0;       // the audio clock's rate against the wall clock's, minus one, in ppm
    std::uint64_t clipped_samples = 0;    // past full scale, after the output stage
    double output_gain_db = 0.0;          // the level gain and the gain in effect (targets of their ramps)
};

// When a block plays, as the backend's clock filter sees it (audio thread, given to process()).
// One command as the engine applied it, for --record-score (server/take_recording.hpp): the sample it
// took effect at (its timetag's, or the block's first when it was untimed or late: max(frame, block
// start), which is exactly when the renderer applies it) and the command with its SI values as the
// engine got them, so an offline render of the take schedules the same commands at the same samples.
struct AppliedCommand {
    std::uint64_t frame = 0;
    Command command;
};
static_assert(std::is_trivially_copyable_v<AppliedCommand>);

struct BlockTime {
    bool valid = false;          // false: no filtered clock; the callback's own wall-clock reading is used
    std::int64_t unix_ns = 0;    // CLOCK_REALTIME (ns since 1970) at which the block's first frame plays
    double rate_ratio = 1.0;     // the card's real sample rate / the nominal one (1 + ppm * 1e-6)
};

// One published (frame, wall time) pair of the audio clock: every message of a packet is timed
// against the same pair, so the messages of one bundle keep their exact distances in samples.
struct AudioClock {
    bool valid = false;               // false before the first block
    std::uint64_t frame = 0;
    std::int64_t unix_ns = 0;
    double sample_rate = 48000.0;     // frames per wall-clock second: nominal x the backend's rate ratio
};
std::uint64_t frame_at(const AudioClock& clock, double unix_seconds);

class AudioBridge {
public:
    AudioBridge(std::unique_ptr<Renderer> renderer, std::size_t queue_capacity, std::unique_ptr<BinauralStage> binaural = nullptr);
    ~AudioBridge();

    // control thread
    bool send(const Command& command) { return commands_.try_push(command); }
    bool poll_event(RendererEvent& event) { return events_.try_pop(event); }
    AudioSnapshot snapshot() const;
    double take_cpu_peak_percent();   // the peak since the previous call, then starts a new one
    // The sample at which a wall-clock time (s since 1970) falls, from the last published block.
    // Before the first block: 0 (timed commands are then applied at once and counted late).
    std::uint64_t frame_for(double unix_seconds) const { return frame_at(clock(), unix_seconds); }
    AudioClock clock() const;
    bool take_meter(MeterWindow& window) { return meter_.take(window); }
    LoudnessTap& loudness_tap() { return loudness_; }   // /meter's loudness: set_wanted, drain (loudness_tap.hpp)
    double sample_rate() const { return sample_rate_; }
    int channels() const { return channels_; }   // the outputs': binaural 2 (the renderer's bus: config().channels)
    const RendererConfig& config() const { return renderer_->config(); }   // fixed at construction
    // Before the backend starts (allocates a ring of `capacity` records): from then on every block's wall
    // and CPU time, page faults and work go into it, for --block-trace.
    void enable_block_trace(std::size_t capacity) { trace_ = std::make_unique<BlockTrace>(capacity); }
    BlockTrace* block_trace() { return trace_.get(); }
    // Before the backend starts (allocates a queue of `capacity` records): from then on every command the
    // renderer accepted (all but /sync's, whose only effect is a reply, and those refused busy) goes into it.
    void enable_take(std::size_t capacity) { take_ = std::make_unique<SpscQueue<AppliedCommand>>(capacity); }
    SpscQueue<AppliedCommand>* take() { return take_.get(); }
    std::uint64_t take_lost() const { return take_lost_.load(std::memory_order_relaxed); }
    bool offer_binaural(std::unique_ptr<BinauralStage>& stage);   // true: taken (stage is then null)
    std::unique_ptr<BinauralStage> take_retired_binaural();
    int binaural_block() const { return binaural_block_.load(std::memory_order_relaxed); }
    std::uint64_t binaural_unmatched_blocks() const { return binaural_unmatched_.load(std::memory_order_relaxed); }

    // audio thread
    void process(int frames, float* const* outputs, const BlockTime& time = {});

private:
    std::unique_ptr<Renderer> renderer_;
    const double sample_rate_;
    const int channels_;
    SpscQueue<Command> commands_;
    SpscQueue<RendererEvent> events_;
    LevelMeter meter_;
    LoudnessTap loudness_;
    std::unique_ptr<BlockTrace> trace_;   // null unless --block-trace
    std::unique_ptr<SpscQueue<AppliedCommand>> take_;   // null unless --record-score
    std::atomic<std::uint64_t> take_lost_{0};
    // --format binaural: the stage playing (owned: freed by the destructor), and the lock-free handoff of
    // its replacements (in) and of the stages they replaced (out, freed on the control thread).
    BinauralStage* binaural_ = nullptr;
    SpscQueue<BinauralStage*> binaural_in_{4};
    SpscQueue<BinauralStage*> binaural_out_{8};
    std::atomic<int> binaural_block_{0};
    std::uint64_t ear_clipped_ = 0;   // audio thread's: binaural ear samples past full scale (snapshot's clipped)
    std::atomic<std::uint64_t> binaural_unmatched_{0};

    // published by the audio thread
    std::atomic<std::uint64_t> clock_sequence_{0};
    std::atomic<std::uint64_t> clock_frame_{0};
    std::atomic<std::int64_t> clock_unix_ns_{0};
    std::atomic<double> clock_rate_ratio_{1.0};
    std::atomic<std::uint64_t> frames_{0}, drops_{0}, late_{0}, busy_{0}, resets_{0}, events_lost_{0}, callbacks_{0};
    std::atomic<int> active_impacts_{0}, active_full_drops_{0}, active_grains_{0};
    std::atomic<double> rain_rate_{0.0};
    std::atomic<std::uint64_t> clipped_{0};
    std::atomic<double> output_gain_db_{0.0};
    std::atomic<double> load_average_{0.0};
    std::atomic<double> load_peak_{0.0};
    static_assert(std::atomic<double>::is_always_lock_free && std::atomic<std::uint64_t>::is_always_lock_free);
};

}  // namespace ameoto
