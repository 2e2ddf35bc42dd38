// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Scene management: the first scene (--scene), and every later change that needs a new scene built
// (/scene/load, /scene/save, /rain/dsd, /surface/..., /accuracy, /material/surface, /material/liquid), and the
// level a loaded scene plays at (--level auto: its gain chosen on the worker, level_choice.hpp):
// checked here, built on the worker thread, handed to the audio thread by pointer, answered /done once
// the audio thread has swapped it in (audio_events.hpp) or /fail with the reason, changing nothing.
// It also keeps what the decoder checks requests against: the surfaces a /drop may land on (a copy of
// the umbrella's geometry) and the liquids and materials defined over OSC.
//
// Interface:
//   std::optional<FirstScene> first = read_first_scene(options, backend.sample_rate(), life.live());   // nullopt: said why
//   SceneManager scenes(io, *first, bridge, record, replies, traffic);
//   scenes.context()                          // protocol::ProtocolContext for protocol::receive_packet
//   scenes.load(peer, "/scene/load", name);   // a built-in scene or NAME.scene from the folder
//   scenes.edit(peer, address, edit);         // /rain/dsd, /surface/add|set|remove, /accuracy
//   scenes.save(peer, "/scene/save", name);   // the record's scene, written atomically to the folder
//   scenes.change_material(peer, address, m); // the umbrella's material (defined by name if it is new)
//   scenes.change_liquid(peer, address, l);   // the liquid (likewise)
//   scenes.done_address(reply_to)             // a load's /done: the address it answers, in order per client
//   scenes.set_loudness(peer, "/loudness", lufs)   // --level auto's target
//   scenes.level()                            // the level in effect (/loudness's query)
//   scenes.record_take(&take)                 // --record-score: each scene change noted before it is sent
//
// Threads: every call on the control thread. The build and file jobs run on the worker (worker.hpp),
// one at a time in order, and see only what they were given by value, plus the scene settings that
// only the worker's jobs touch (so a liquid change after a surface change builds on that surface).

#include <boost/asio/io_context.hpp>

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "engine/render/renderer.hpp"
#include "engine/scene/scene_description.hpp"
#include "protocol/address_table.hpp"
#include "server/level_state.hpp"
#include "server/options.hpp"
#include "server/osc/peer.hpp"
#include "server/osc/traffic_counters.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/replies.hpp"
#include "server/scene_record.hpp"
#include "server/take_recording.hpp"
#include "server/worker.hpp"

namespace ameoto {

// The scene ameotod starts with, read and configured before anything is built.
struct FirstScene {
    SceneDescription scene;
    RendererConfig base;     // the stream's (rate, channels, seed, adaptive detail), before any scene
    RendererConfig config;   // base with the scene's settings
    std::shared_ptr<const UmbrellaParts> parts;   // its umbrella, built once for --level auto and the stream
                                                  // (Renderer(config, parts.get())); let go once it plays
    std::filesystem::path folder;   // the scene folder (--scene-dir)
    LevelState level;        // --level, --loudness, --limiter, and what auto chose for this scene
    double default_rain_mm_per_h = 0.0;   // the scene's own rain (before --rain), what auto measured
};

// --scene NAME (built in, or NAME.scene in the folder) or --scene PATH.scene (a file anywhere: the
// command line is trusted), then --rain, --gain; with --level auto its level gain is chosen (level_choice.hpp:
// 3 s of its default rain rendered and measured, on the calling thread, before audio starts).
// Says why and returns nullopt when it cannot be read or used.
std::optional<FirstScene> read_first_scene(const DaemonOptions& options, double sample_rate, bool live);

class SceneManager {
public:
    SceneManager(boost::asio::io_context& io, const FirstScene& first, AudioBridge& bridge, SceneRecord& record,
                 Replies& replies, TrafficCounters& traffic);
    SceneManager(const SceneManager&) = delete;
    SceneManager& operator=(const SceneManager&) = delete;

    const protocol::ProtocolContext& context() const { return context_; }
    void load(const Peer& sender, const std::string& address, const std::string& name);
    void edit(const Peer& sender, const std::string& address, const protocol::SceneEdit& edit);
    void save(const Peer& sender, const std::string& address, const std::string& name);
    void change_material(const Peer& sender, const std::string& address, const MembraneMaterial& material);
    void change_liquid(const Peer& sender, const std::string& address, const Liquid& liquid);
    std::string done_address(std::uint16_t reply_to);
    // /loudness: --level auto's target; the scene playing moves to it (ramped, once the worker has found its
    // gain through the limiter from the choice's recording), later loads are set to it.
    void set_loudness(const Peer& sender, const std::string& address, double target_lufs);
    const LevelState& level() const { return level_; }
    void record_take(TakeRecording* take) { take_ = take; }

    // What the audio thread's scene is made of, as the worker last built it: only the worker's jobs
    // touch it, one at a time in order, so a refused change leaves it as it was.
    struct WorkerSettings {
        MembraneMaterial material;
        Liquid liquid;
    };

private:
    // choose_level: a load (--level auto measures the new scene); an edit keeps the level gain it has.
    void build_and_load(const Peer& sender, const std::string& address, std::function<SceneDescription()> source,
                        bool choose_level);
    void rebuild(const Peer& sender, const std::string& address, std::optional<MembraneMaterial> material,
                 std::optional<Liquid> liquid);
    void use_geometry(const RendererConfig& config, bool has_umbrella);
    void fail(std::uint16_t reply_to, const std::string& address, const std::string& reason);
    void send_level(std::uint16_t reply_to, const std::string& address, double gain_db, double previous_target);

    AudioBridge& bridge_;
    SceneRecord& record_;
    Replies& replies_;
    TrafficCounters& traffic_;
    RendererConfig base_config_;
    std::filesystem::path folder_;
    std::unique_ptr<Canopy> geometry_;   // the control thread's own copy of the surface, for validating points
    protocol::ProtocolContext context_;
    std::map<std::string, Liquid> custom_liquids_;
    std::map<std::string, MembraneMaterial> custom_materials_;
    std::map<std::uint16_t, std::deque<std::string>> pending_done_;   // per client: scene rebuilds sent, in order
    std::shared_ptr<WorkerSettings> worker_settings_;
    LevelState level_;
    TakeRecording* take_ = nullptr;   // --record-score, else null
    Worker worker_;   // last: joined first, before anything a job's result would touch goes
};

}  // namespace ameoto
