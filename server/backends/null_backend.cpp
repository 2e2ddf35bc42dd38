// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/null_backend.hpp"

#include <pthread.h>
#include <time.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "server/backends/realtime_pace.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/wall_offset.hpp"

namespace ameoto {
namespace {
std::int64_t monotonic_ns() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return static_cast<std::int64_t>(t.tv_sec) * 1000000000 + t.tv_nsec;
}
}  // namespace

NullBackend::NullBackend(const Options& options, std::function<void()> on_finished)
    : options_(options), on_finished_(std::move(on_finished)) {
    if (options_.output != "-") wav_ = std::make_unique<WavWriter>(options_.output, options_.channels, options_.sample_rate);
}

NullBackend::~NullBackend() { stop(); }

void NullBackend::start(AudioBridge& bridge) {
    stop_.store(false);
    thread_ = std::thread([this, &bridge] { run(bridge); });
    pthread_setname_np(thread_.native_handle(), "ameoto-render");
    const int priority = options_.realtime_priority;
    if (!options_.realtime) {
        scheduling_ = "normal scheduling (offline render)";
    } else if (priority == 0) {
        scheduling_ = "normal scheduling (--realtime-priority 0)";
    } else {
        sched_param param{};
        param.sched_priority = priority;
        const int error = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param);
        scheduling_ = error == 0 ? "SCHED_FIFO priority " + std::to_string(priority)
                                 : "normal scheduling: SCHED_FIFO priority " + std::to_string(priority) + " refused (" +
                                       std::strerror(error) +
                                       "; run as root or give the user an rtprio limit, e.g. JACK's audio group)";
    }
}

void NullBackend::stop() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    if (wav_) wav_->close();
}

void NullBackend::run(AudioBridge& bridge) {
    const int block = options_.block_size;
    const int channels = options_.channels;
    // Everything the loop touches is allocated here, before the first block.
    std::vector<std::vector<float>> planes(static_cast<std::size_t>(channels), std::vector<float>(static_cast<std::size_t>(block)));
    std::vector<float*> outputs;
    for (auto& p : planes) outputs.push_back(p.data());
    std::vector<float> interleaved(static_cast<std::size_t>(block * channels));

    const std::uint64_t total_frames = options_.duration_s
        ? static_cast<std::uint64_t>(std::llround(*options_.duration_s * options_.sample_rate))
        : UINT64_MAX;
    const std::int64_t start_ns = monotonic_ns();
    RealtimePace pace(block / options_.sample_rate, start_ns);
    std::int64_t deadline_ns = start_ns;   // paced: the grid boundary the block in hand starts at
    std::uint64_t done = 0;

    while (!stop_.load(std::memory_order_relaxed) && done < total_frames) {
        const int frames = static_cast<int>(std::min<std::uint64_t>(static_cast<std::uint64_t>(block), total_frames - done));
        if (!options_.realtime && wav_) {
            // Offline: wait for the disk rather than lose audio.
            while (wav_->space_frames() < static_cast<std::size_t>(frames) && !stop_.load()) {
                timespec pause{0, 1000000};
                nanosleep(&pause, nullptr);
            }
        }
        // Paced, a block is timed by its place on the grid, not by when this thread woke (which jitters
        // by the scheduler's latency): bundles of separate packets keep their distances to the sample.
        BlockTime time;
        if (options_.realtime) {
            time.valid = true;
            time.unix_ns = deadline_ns + realtime_minus_monotonic_ns();
        }
        bridge.process(frames, outputs.data(), time);
        if (wav_) {
            for (int n = 0; n < frames; ++n)
                for (int c = 0; c < channels; ++c)
                    interleaved[static_cast<std::size_t>(n * channels + c)] = planes[static_cast<std::size_t>(c)][static_cast<std::size_t>(n)];
            if (!wav_->push(interleaved.data(), frames)) xruns_.fetch_add(1);
        }
        done += static_cast<std::uint64_t>(frames);
        if (options_.realtime) {
            const RealtimePace::Next next = pace.after_block(monotonic_ns());
            if (next.late) xruns_.fetch_add(1);
            deadline_ns = next.wake_ns;
            const timespec wake{static_cast<time_t>(next.wake_ns / 1000000000), static_cast<long>(next.wake_ns % 1000000000)};
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &wake, nullptr);
        }
    }
    if (done >= total_frames && on_finished_) on_finished_();
}

}  // namespace ameoto
