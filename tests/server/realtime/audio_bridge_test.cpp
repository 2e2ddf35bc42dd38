// SPDX-License-Identifier: GPL-3.0-or-later
// The real-time contract, proven: everything the audio thread runs (AudioBridge::process: queue
// drain, Renderer::process with rain, drops, rate changes and syncs, event and stats publishing)
// calls no allocator, lock, sleep or write. The probe (tests/support/rt_interposer.cpp) is linked
// into this binary; the first test shows it catches planted violations, so a pass is meaningful.

#include "server/realtime/audio_bridge.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/render/binaural_decoder.hpp"
#include "server/realtime/binaural_stage.hpp"
#include "server/realtime/rt_probe.hpp"
#include "tests/support/rt_probe_scope.hpp"   // the probe's counters (ameoto_rt_probe_*)

namespace {

struct ProbeFixture {
    ProbeFixture() {
        ameoto::rt::init_probe();
        REQUIRE(bool(ameoto::rt::probe_enter));   // the probe must be live, or nothing is checked
        ameoto_rt_probe_reset();
    }
};

__attribute__((noinline)) void planted_allocation() {
    ameoto::rt::Scope scope;
    auto* volatile p = new int(42);
    delete p;
}

}  // namespace

TEST_CASE_FIXTURE(ProbeFixture, "the probe catches planted violations in the audio scope") {
    SUBCASE("allocation") {
        planted_allocation();
        CHECK(ameoto_rt_probe_violations() >= 1);
        CHECK(std::string(ameoto_rt_probe_first_violation()) == "malloc");
    }
    SUBCASE("a mutex") {
        std::mutex m;
        {
            ameoto::rt::Scope scope;
            m.lock();
            m.unlock();
        }
        CHECK(std::string(ameoto_rt_probe_first_violation()) == "pthread_mutex_lock");
    }
    SUBCASE("logging") {
        std::FILE* sink = std::fopen("/dev/null", "w");
        REQUIRE(sink != nullptr);
        static volatile int value = 7;
        {
            ameoto::rt::Scope scope;
            std::fprintf(sink, "callback took %d us\n", value);
        }
        std::fclose(sink);
        CHECK(ameoto_rt_probe_violations() >= 1);
    }
    SUBCASE("sleeping") {
        {
            ameoto::rt::Scope scope;
            std::this_thread::sleep_for(std::chrono::microseconds(1));
        }
        CHECK(std::string(ameoto_rt_probe_first_violation()) == "nanosleep");
    }
    SUBCASE("outside the scope nothing counts") {
        auto* p = new int(1);
        delete p;
        CHECK(ameoto_rt_probe_violations() == 0);
    }
}

TEST_CASE_FIXTURE(ProbeFixture, "AudioBridge::process never allocates, frees, locks, sleeps or logs") {
    ameoto::RendererConfig config;
    config.rain_rate_mm_per_h = 100.0;   // heavy rain: many impacts start and end in every block
    config.channels = 4;
    config.limiter = true;                // the output stage's look-ahead limiter, and gains to ramp
    config.level_gain_db = 30.0;          // loud enough that the limiter works in every block
    ameoto::AudioBridge bridge(std::make_unique<ameoto::Renderer>(config), 256);
    bridge.loudness_tap().set_wanted(true);   // /meter's loudness: the samples handed over (drained below)
    bridge.enable_take(1024);                 // --record-score: every applied command into its queue (drained below)
    constexpr int block = 256;
    std::vector<std::vector<float>> planes(4, std::vector<float>(block));
    std::vector<float*> outputs{planes[0].data(), planes[1].data(), planes[2].data(), planes[3].data()};

    // A control thread floods commands (drops, rate changes, syncs, far-future timed drops that fill
    // the pending list and produce busy events, gain and level changes that ramp) while the audio thread
    // renders, and drains the loudness tap into a libebur128 meter as the daemon's /meter does.
    ameoto::LoudnessMeter loudness(4, config.sample_rate, ameoto::LoudnessMeter::short_term | ameoto::LoudnessMeter::peaks);
    std::atomic<bool> done{false};
    std::atomic<long> recorded{0};
    std::thread control([&] {
        int i = 0;
        while (!done.load()) {
            ameoto::Command c;
            switch (i % 6) {
                case 0: c.kind = ameoto::CommandKind::drop; c.values[0] = 0.004; c.values[2] = 0.2; break;
                case 1: c.kind = ameoto::CommandKind::rain_rate; c.values[0] = (i % 400) * 1.0; break;
                case 2: c.kind = ameoto::CommandKind::sync; c.id = i; break;
                case 3: c.kind = ameoto::CommandKind::drop; c.timed = true; c.frame = 1'000'000'000; c.values[0] = 0.002; c.values[2] = 0.2; break;
                case 4: c.kind = ameoto::CommandKind::gain; c.values[0] = (i % 7) * 3.0 - 9.0; break;
                case 5: c.kind = ameoto::CommandKind::level; c.values[0] = 20.0 + (i % 5) * 4.0; break;
            }
            (void)bridge.send(c);
            ameoto::RendererEvent e;
            while (bridge.poll_event(e)) {}
            ameoto::AppliedCommand applied;
            while (bridge.take()->try_pop(applied)) recorded.fetch_add(1, std::memory_order_relaxed);
            if (i % 64 == 0) bridge.loudness_tap().drain(loudness);
            ++i;
            if (i % 64 == 0) std::this_thread::yield();
        }
    });
    std::thread audio([&] {
        for (int n = 0; n < 2000; ++n) bridge.process(block, outputs.data());
    });
    audio.join();
    done.store(true);
    control.join();

    const ameoto::AudioSnapshot s = bridge.snapshot();
    CHECK(s.drops > 1000);            // the workload really ran
    CHECK(s.busy_commands > 0);       // including the overflow path
    CHECK(recorded.load() > 1000);    // and the take's path (a full queue counted in take_lost)
    CHECK(s.clipped_samples == 0);    // the limiter held the ceiling through every gain change
    CHECK(ameoto_rt_probe_entries() == 2000);
    INFO("first violation: " << std::string(ameoto_rt_probe_first_violation()));
    CHECK(ameoto_rt_probe_violations() == 0);
}

TEST_CASE("AudioBridge maps wall-clock time to sample time from the last block") {
    ameoto::RendererConfig config;
    config.rain_rate_mm_per_h = 0.0;
    ameoto::AudioBridge bridge(std::make_unique<ameoto::Renderer>(config), 16);
    CHECK(bridge.frame_for(1e9) == 0);   // nothing published yet
    std::vector<float> l(480), r(480);
    float* outs[2] = {l.data(), r.data()};
    auto wall = [] {
        timespec now{};
        clock_gettime(CLOCK_REALTIME, &now);
        return static_cast<double>(now.tv_sec) + now.tv_nsec * 1e-9;
    };
    bridge.process(480, outs);
    const double before = wall();
    bridge.process(480, outs);           // this block started at frame 480, at a time in [before, after]
    const double after = wall();
    // frame_for(after + 1 s) = 480 + (after + 1 - block_start) * 48000, with block_start in [before, after].
    const auto f = static_cast<double>(bridge.frame_for(after + 1.0));
    CHECK(f >= 480 + 48000 - 1);
    CHECK(f <= 480 + 48000 + (after - before) * 48000 + 1);
}

TEST_CASE_FIXTURE(ProbeFixture, "AudioBridge::process on an Ambisonic stream, the head turning, never allocates, frees, locks or sleeps") {
    ameoto::RendererConfig config;
    config.rain_rate_mm_per_h = 50.0;   // panels, texture grains and the bus rotation all busy
    std::string error;
    ameoto::apply_output_format(config, *ameoto::parse_output_format("ambix:1", error));
    ameoto::AudioBridge bridge(std::make_unique<ameoto::Renderer>(config), 256);
    constexpr int block = 256;
    std::vector<std::vector<float>> planes(4, std::vector<float>(block));
    std::vector<float*> outputs{planes[0].data(), planes[1].data(), planes[2].data(), planes[3].data()};
    // The control thread turns the head over and over (a tracker far faster than any: every turn starts
    // mid-glide), building each matrix itself as packet_dispatch.cpp does, and frees what comes back.
    std::atomic<bool> done{false};
    std::atomic<int> returned{0};
    std::thread control([&] {
        int i = 0;
        while (!done.load()) {
            ameoto::Command c;
            c.kind = ameoto::CommandKind::orientation;
            c.values[0] = 0.1 * (i % 60);
            c.values[1] = 0.05 * (i % 7);
            c.object = new ameoto::AmbixRotation(ameoto::AmbixRotation::from_orientation(c.values[0], c.values[1], 0.0, 1));
            if (!bridge.send(c)) delete static_cast<ameoto::AmbixRotation*>(c.object);
            ameoto::RendererEvent e;
            while (bridge.poll_event(e))
                if (e.kind == ameoto::RendererEventKind::retired && e.object_type == ameoto::RetiredObject::rotation) {
                    delete static_cast<ameoto::AmbixRotation*>(e.object);
                    returned.fetch_add(1);
                }
            ++i;
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    });
    std::thread audio([&] {
        for (int n = 0; n < 500; ++n) bridge.process(block, outputs.data());
    });
    audio.join();
    done.store(true);
    control.join();
    CHECK(returned.load() > 10);   // the turns really reached the audio thread and came back
    CHECK(ameoto_rt_probe_entries() == 500);
    INFO("first violation: " << std::string(ameoto_rt_probe_first_violation()));
    CHECK(ameoto_rt_probe_violations() == 0);
}

TEST_CASE_FIXTURE(ProbeFixture, "AudioBridge::process on a binaural stream, its block size changing, never allocates, frees, locks or sleeps") {
    // --format binaural: the renderer's third-order bus into the stage's own bus, decoded to two ears; the
    // head turning meanwhile; then JACK's buffer size halves (a stage for 128 frames handed over as
    // server/binaural_supply.cpp does), then doubles back before a stage for it came (rendered in pieces,
    // silence), and a short last block (padded); the ears' limiter on (its preallocated delay line). Every
    // block under the probe.
    ameoto::RendererConfig config;
    config.rain_rate_mm_per_h = 50.0;
    std::string error;
    ameoto::apply_output_format(config, *ameoto::parse_output_format("binaural", error));
    REQUIRE(config.channels == 16);
    auto first = ameoto::BinauralStage::create(ameoto::BinauralDecoder::default_sofa_path, 3, config.sample_rate, 256, true);
    INFO(first.error);
    REQUIRE(first.stage);
    auto second = ameoto::BinauralStage::create(ameoto::BinauralDecoder::default_sofa_path, 3, config.sample_rate, 128, true);
    REQUIRE(second.stage);
    ameoto::AudioBridge bridge(std::make_unique<ameoto::Renderer>(config), 256, std::move(first.stage));
    CHECK(bridge.channels() == 2);
    CHECK(bridge.binaural_block() == 256);
    std::vector<std::vector<float>> ears(2, std::vector<float>(256));
    std::vector<float*> outputs{ears[0].data(), ears[1].data()};
    std::atomic<bool> done{false};
    std::atomic<int> returned{0};
    std::thread control([&] {
        int i = 0;
        while (!done.load()) {
            ameoto::Command c;
            c.kind = ameoto::CommandKind::orientation;
            c.values[0] = 0.1 * (i % 60);
            c.object = new ameoto::AmbixRotation(ameoto::AmbixRotation::from_orientation(c.values[0], 0.0, 0.0, 3));
            if (!bridge.send(c)) delete static_cast<ameoto::AmbixRotation*>(c.object);
            ameoto::RendererEvent e;
            while (bridge.poll_event(e))
                if (e.kind == ameoto::RendererEventKind::retired && e.object_type == ameoto::RetiredObject::rotation) {
                    delete static_cast<ameoto::AmbixRotation*>(e.object);
                    returned.fetch_add(1);
                }
            ++i;
            std::this_thread::sleep_for(std::chrono::microseconds(500));
        }
    });
    double heard = 0.0, over_long = 0.0;
    auto energy = [&](int frames) {
        double e = 0.0;
        for (const auto& ear : ears)
            for (int n = 0; n < frames; ++n) e += static_cast<double>(ear[static_cast<std::size_t>(n)]) * ear[static_cast<std::size_t>(n)];
        return e;
    };
    std::thread audio([&] {
        for (int n = 0; n < 200; ++n) bridge.process(256, outputs.data());
        heard = energy(256);
    });
    audio.join();
    CHECK(bridge.offer_binaural(second.stage));   // the control thread's handoff (binaural_supply.cpp)
    CHECK(!second.stage);
    std::thread audio2([&] {
        for (int n = 0; n < 200; ++n) bridge.process(128, outputs.data());
        heard += energy(128);
        for (int n = 0; n < 20; ++n) {
            bridge.process(256, outputs.data());   // longer than the stage's: pieces rendered, silence out
            over_long += energy(256);
        }
        bridge.process(100, outputs.data());       // shorter: decoded padded
    });
    audio2.join();
    done.store(true);
    control.join();
    CHECK(bridge.binaural_block() == 128);
    CHECK(bridge.binaural_unmatched_blocks() == 21);
    CHECK(bridge.take_retired_binaural() != nullptr);   // the 256-frame stage, back to be freed here
    CHECK(bridge.take_retired_binaural() == nullptr);
    CHECK(heard > 0.0);           // the ears really carry the rain
    CHECK(over_long == 0.0);
    CHECK(bridge.snapshot().frames == 200 * 256 + 200 * 128 + 20 * 256 + 100);   // the scene's time ran on throughout
    CHECK(returned.load() > 10);
    CHECK(ameoto_rt_probe_entries() == 421);
    INFO("first violation: " << std::string(ameoto_rt_probe_first_violation()));
    CHECK(ameoto_rt_probe_violations() == 0);
}
