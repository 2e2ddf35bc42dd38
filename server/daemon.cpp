// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/daemon.hpp"

#include <time.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "engine/render/renderer.hpp"
#include "server/audio_events.hpp"
#include "server/backend_life.hpp"
#include "server/binaural_supply.hpp"
#include "server/block_tracing.hpp"
#include "server/control_loop.hpp"
#include "server/log_lines.hpp"
#include "server/memory_return.hpp"
#include "server/osc/traffic_counters.hpp"
#include "server/osc_intake.hpp"
#include "server/output_choice.hpp"
#include "server/packet_dispatch.hpp"
#include "server/peers.hpp"
#include "server/queries.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/rt_probe.hpp"
#include "server/replies.hpp"
#include "server/scene_manager.hpp"
#include "server/scene_record.hpp"
#include "server/status.hpp"
#include "server/subscriptions.hpp"
#include "server/systemd_notify.hpp"
#include "server/take_recording.hpp"
#include "server/watchdog.hpp"

namespace ameoto {

using namespace std::chrono_literals;

int Daemon::run() {
    rt::init_probe();
    ControlLoop loop;   // SIGINT, SIGTERM and SIGHUP are caught from here on, and handled once it runs
    SystemdNotifier systemd;
    TrafficCounters traffic;

    // The output format before the backend: its channels are the ports' and the WAV's.
    if (!resolve_output_format(options_)) return 1;
    say("output " + output_channel_summary(*options_.format));

    // The backend first: its sample rate decides the physics' time step. The null backend ends a
    // --duration render from its own thread.
    const std::unique_ptr<BackendLife> life = BackendLife::choose(options_, systemd, [&loop] { loop.shutdown_soon(); });
    if (!life) return 1;

    // The ports next: a port in use is reported at once, not after the scene's seconds of building.
    // Nothing is read from them before the loop runs; what arrives meanwhile waits in the kernel's buffers.
    Replies replies;
    OscIntake intake(loop.io(), options_, replies, traffic);
    if (!intake.bind()) return 1;
    replies.send_through(intake.udp(), intake.tcp());

    // The take's file (--record-score), so an unwritable one is said before the scene's seconds of building.
    TakeRecording take;
    if (!take.open(options_)) return 1;

    // The scene, and the bridge the audio thread plays it through.
    std::optional<FirstScene> first = read_first_scene(options_, life->backend().sample_rate(), life->live());
    if (!first) return 1;
    // --format binaural: the decoder for the backend's block size, built before audio starts (libmysofa reads
    // and resamples the SOFA file: about 2 s the first time at a rate); the renderer makes its AmbiX bus.
    std::unique_ptr<BinauralStage> ears;
    const int binaural_order = options_.format->kind == OutputKind::binaural ? options_.format->order : 0;
    if (binaural_order > 0) {
        BinauralStage::Made made =
            BinauralStage::create(options_.hrtf, binaural_order, life->backend().sample_rate(), life->backend().block_size(),
                                  options_.limiter_on());   // the limiter acts on the ears (binaural_stage.hpp)
        if (!made.stage) {
            warn("--format binaural: " + made.error);
            return 1;
        }
        say("binaural: " + options_.hrtf + ", order " + std::to_string(binaural_order) + ", blocks of " +
            std::to_string(made.stage->block_frames()) + " frames, " + std::to_string(made.stage->filter_frames()) + "-tap filters" +
            (made.stage->limiter() ? ", the limiter on the ears (" + std::to_string(made.stage->latency_frames()) + " frames' look-ahead)"
                                   : ""));
        ears = std::move(made.stage);
    }
    AudioBridge bridge(std::make_unique<Renderer>(first->config, first->parts.get()), 4096, std::move(ears));
    first->parts.reset();   // the renderer has its copy
    std::optional<BinauralSupply> binaural;
    if (binaural_order > 0) binaural.emplace(loop.io(), bridge, options_.hrtf, binaural_order, life->backend().sample_rate(), options_.limiter_on());
    BlockTracing tracing(bridge);
    if (!tracing.open(options_, life->backend().sample_rate())) return 1;
    SceneRecord record(first->scene, first->config.liquid, first->config.material);
    SceneManager scenes(loop.io(), *first, bridge, record, replies, traffic);
    if (!take.begin(*first, bridge)) return 1;
    if (take.on()) scenes.record_take(&take);
    say("scene " + record.scene().name);
    const std::string level = describe_level(first->level, first->scene.name, first->default_rain_mm_per_h, first->scene.gain_db);
    say(level);
    life->set_wav_comment("ameotod " AMEOTO_VERSION ": " + level +
                          ". Samples are sound pressure at the listener: pressure in Pa = sample x 10^((0 dBFS in dB SPL - 93.98) / 20)"
                          " (gain changes over OSC after the start are in ameotod's log). Channels: " +
                          output_channel_summary(*options_.format));

    // What the control thread answers with, and what a packet becomes.
    StatusReport status(bridge, life->backend());
    Subscriptions subscriptions(replies, status, bridge, life->backend());
    Queries queries(record, replies, subscriptions, scenes.level(), intake.udp_port(), intake.tcp_port());
    PeerSet peers(options_.peers, options_.peer_latency_s, replies);
    peers.send_through(intake.udp());
    PacketDispatch dispatch(bridge, scenes, record, replies, queries, subscriptions, status, traffic, [&loop] { loop.shutdown_soon(); },
                            peers);
    AudioEvents events(bridge, replies, scenes, traffic);
    Watchdog watchdog(systemd);

    intake.say_where();
    life->announce();
    loop.on_hangup([&] { life->hangup(); });
    loop.on_shutdown([&] {
        systemd.stopping();
        intake.close();
    });

    // Play, and serve.
    life->start(bridge);
    intake.start(dispatch, status);
    loop.every(5ms, [&] {
        if (events.handle()) return_free_memory();   // RSS follows what is held (memory_return.hpp)
        tracing.drain();
        const AudioSnapshot s = bridge.snapshot();
        record.apply_due(s.frames);
        subscriptions.send_meters();
        life->watch(s, replies);   // "running" and READY=1 after the first block; WAV and JACK faults
        if (binaural) binaural->watch(life->backend().block_size());   // JACK's buffer size changed: a new decoder
    });
    auto traffic_reported = std::chrono::steady_clock::now();
    loop.every(1s, [&] {
        status.measure_rate();
        // The load counters, at most every 5 s and only when they changed.
        if (const auto now = std::chrono::steady_clock::now(); now - traffic_reported >= 5s) {
            if (const auto line = traffic.report_if_changed()) say(*line);
            traffic_reported = now;
        }
    });
    loop.every(1s, [&] { subscriptions.send_status(); });
    if (take.on()) loop.every(100ms, [&] { take.drain(); });
    if (!peers.empty()) {
        say("conducting " + std::to_string(options_.peers.size()) + " peers, commands timed " +
            std::to_string(static_cast<int>(std::lround(options_.peer_latency_s * 1e3))) + " ms ahead");
        loop.every(250ms, [&] {
            timespec t{};
            clock_gettime(CLOCK_REALTIME, &t);
            peers.tick(static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9);
        });
    }
    if (watchdog.interval().count() > 0) loop.every(watchdog.interval(), [&] { watchdog.feed(bridge.snapshot().frames); });
    loop.run();

    // Stop in order: the TCP thread reads the bridge and the backend, so it goes before them; the
    // audio thread before the trace's last records and the WAV's count are read.
    intake.close();
    life->stop();
    tracing.finish();
    take.finish();
    if (traffic.busy > 0 || traffic.refused_senders > 0) say(traffic.report());
    life->report_written();
    say("stopped");
    return 0;
}

}  // namespace ameoto
