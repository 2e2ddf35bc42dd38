// SPDX-License-Identifier: GPL-3.0-or-later
// The listener's turns on the audio thread (renderer_listener.cpp) under the allocation/lock probe: a
// tracker's stream of /listener/orientation and /listener facing changes, each starting mid-glide, on
// stereo (the panels and surfaces re-panned) and on Ambisonics (the world bus turned by the facing, the
// whole bus by the head).

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/rt_probe.hpp"
#include "tests/support/rt_probe_scope.hpp"   // the probe's counters (ameoto_rt_probe_*)

namespace turn_probe {

constexpr int blocks = 120;   // 0.64 s of audio: dozens of turns, each starting mid-glide

// The umbrella with a plate 3 m to the left: a held umbrella and a world surface, both turned.
ameoto::RendererConfig umbrella_and_plate(const char* format) {
    ameoto::SceneDescription scene = *ameoto::builtin_scene("umbrella");
    ameoto::SurfaceDescription plate;
    plate.name = "plate";
    plate.kind = ameoto::SurfaceKind::plate;
    plate.material = "tin";
    plate.size_x_m = plate.size_y_m = 1.0;
    plate.x_m = scene.listener.x_m;
    plate.y_m = scene.listener.y_m + 3.0;
    plate.z_m = scene.listener.z_m;
    scene.surfaces.push_back(plate);
    ameoto::RendererConfig config = ameoto::configure_for_scene(ameoto::RendererConfig{}, scene);
    config.rain_rate_mm_per_h = 50.0;   // panels, grains and the plate all busy
    std::string error;
    ameoto::apply_output_format(config, *ameoto::parse_output_format(format, error));
    return config;
}

// Runs `blocks` blocks while the control thread turns the body and the head over and over; returns the
// rotations that came back (proof the turns reached the audio thread).
int turn_while_playing(const ameoto::RendererConfig& config) {
    const auto listener = config.scene.listener;
    const int order = config.listener == ameoto::ListenerStyle::ambix ? ameoto::ambix_order(config.channels) : 0;
    ameoto::AudioBridge bridge(std::make_unique<ameoto::Renderer>(config), 256);
    constexpr int block = 256;
    std::vector<std::vector<float>> planes(static_cast<std::size_t>(config.channels), std::vector<float>(block));
    std::vector<float*> outputs;
    for (auto& p : planes) outputs.push_back(p.data());
    std::atomic<bool> done{false};
    std::atomic<int> returned{0};
    std::thread control([&] {
        for (int i = 0; !done.load(); ++i) {
            ameoto::Command c;
            if (i % 3 == 0) {
                c.kind = ameoto::CommandKind::listener;
                c.values[0] = listener.x_m;
                c.values[1] = listener.y_m;
                c.values[2] = listener.z_m;
                c.values[3] = 0.2 * (i % 31);
            } else {
                c.kind = ameoto::CommandKind::orientation;
                c.values[0] = 0.1 * (i % 60);
                c.values[1] = 0.05 * (i % 7);
                c.values[2] = 0.07 * (i % 5);
                c.object = new ameoto::AmbixRotation(ameoto::AmbixRotation::from_orientation(c.values[0], c.values[1], c.values[2], order));
            }
            if (!bridge.send(c) && c.object) delete static_cast<ameoto::AmbixRotation*>(c.object);
            ameoto::RendererEvent e;
            while (bridge.poll_event(e))
                if (e.kind == ameoto::RendererEventKind::retired && e.object_type == ameoto::RetiredObject::rotation) {
                    delete static_cast<ameoto::AmbixRotation*>(e.object);
                    returned.fetch_add(1);
                }
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    });
    std::thread audio([&] {
        for (int n = 0; n < blocks; ++n) bridge.process(block, outputs.data());
    });
    audio.join();
    done.store(true);
    control.join();
    return returned.load();
}

}  // namespace turn_probe

TEST_CASE("AudioBridge::process with the body and the head turning, stereo and ambix:3, never allocates, frees, locks or sleeps") {
    for (const char* format : {"stereo", "ambix:3"}) {
        CAPTURE(format);
        const ameoto::RendererConfig config = turn_probe::umbrella_and_plate(format);   // built before the probe counts
        ameoto::rt::init_probe();
        REQUIRE(bool(ameoto::rt::probe_enter));   // the probe must be live, or nothing is checked
        ameoto_rt_probe_reset();
        const int returned = turn_probe::turn_while_playing(config);
        CHECK(returned > 10);
        CHECK(ameoto_rt_probe_entries() == turn_probe::blocks);
        INFO("first violation: " << std::string(ameoto_rt_probe_first_violation()));
        CHECK(ameoto_rt_probe_violations() == 0);
    }
}
