#include "server/daemon.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>

#include "protocol/address_table.hpp"
#include "protocol/receive.hpp"
#include "server/backends/jack_backend.hpp"
#include "server/backends/null_backend.hpp"
#include "server/memory_return.hpp"
#include "server/osc/client_table.hpp"
#include "server/osc/peer.hpp"
#include "server/osc/reply_ports.hpp"
#include "server/osc/tcp_endpoint.hpp"
#include "server/osc/traffic_counters.hpp"
#include "server/osc/cheap_query.hpp"
#include "server/osc/datagram_backlog.hpp"
#include "server/osc/udp_endpoint.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/block_trace.hpp"
#include "server/realtime/rt_probe.hpp"
#include "server/scene_store.hpp"
#include "server/systemd_notify.hpp"
#include "server/worker.hpp"

namespace ameoto {
namespace {

namespace asio = boost::asio;
using namespace std::chrono_literals;

void say(const std::string& line) {
    std::cout << "ameotod: " << line << std::endl;   // flushed: scripts and tests read these lines
}
void warn(const std::string& line) { std::cerr << "ameotod: " << line << std::endl; }

std::string default_wav_name() {
    char name[64];
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    std::strftime(name, sizeof name, "ameoto-%Y%m%d-%H%M%S.wav", &local);
    return unused_path(name);
}

// A live surface may take at most this many sub-steps per sample: each multiplies the canopy's cost, and
// the audio thread must keep its deadline (seed-nylon needs 27 at 48 kHz: about 3 cores). Stiffer
// materials are refused with their bound; offline renders may still use them.
constexpr int max_live_sub_steps = 4;

void check_live_cost(const Canopy& canopy, const MembraneMaterial& material, double sample_rate) {
    const StabilityReport& s = canopy.panel(0).network.stability();
    if (s.sub_steps <= max_live_sub_steps) return;
    char text[320];
    std::snprintf(text, sizeof text,
                  "material '%s' needs %d sub-steps per sample at %.0f Hz (omega_max T = %.1f for the explicit scheme): more than "
                  "the %d a live surface may take; render it offline or choose a softer material",
                  material.name.c_str(), s.sub_steps, sample_rate, s.omega_max_bound / sample_rate, max_live_sub_steps);
    throw std::invalid_argument(text);
}

double degrees(double radians) { return radians * (180.0 / 3.14159265358979323846); }   // replies use the units of the requests

// OSC's i is 32 bits; a counter past that reports the largest value instead of wrapping negative.
std::int32_t saturate_int32(std::uint64_t v) { return v > 2147483647u ? 2147483647 : static_cast<std::int32_t>(v); }

// The server's own replies (docs/PROTOCOL.md, "Replies"). One arriving as a request is another server's
// answer, or this server's own after a /reply/port aimed at a server's port: answering it with /fail
// would start an exchange that never ends, so it is dropped unanswered.
bool is_reply_address(const std::string& address) {
    return address == "/done" || address == "/fail" || address == "/synced" || address == "/notice" || address == "/meter" ||
           (address.size() > 6 && address.ends_with(".reply"));
}

}  // namespace

struct Daemon::State {
    DaemonOptions options;
    asio::io_context io;
    asio::signal_set stop_signals{io, SIGINT, SIGTERM};
    asio::signal_set hup_signal{io, SIGHUP};
    asio::steady_timer poll_timer{io};
    asio::steady_timer rate_timer{io};
    asio::steady_timer watchdog_timer{io};
    std::unique_ptr<Backend> backend;
    JackBackend* jack = nullptr;        // the same object as backend, when it is JACK
    NullBackend* null = nullptr;
    std::unique_ptr<AudioBridge> bridge;
    std::unique_ptr<BlockTraceFile> block_trace;   // --block-trace: fed from the bridge's ring by poll()
    std::unique_ptr<Canopy> geometry;   // the control thread's own copy of the surface, for validating points
    std::map<std::string, Liquid> custom_liquids;
    std::map<std::string, MembraneMaterial> custom_materials;
    std::unique_ptr<Worker> worker;
    std::unique_ptr<UdpEndpoint> udp;
    // UDP datagrams read but not yet handled (docs/reliability.md, "Load"): 8192 is 80 ms of a
    // 100 000/s flood; 2 MiB holds them with room for large bundles.
    DatagramBacklog udp_backlog{8192, 2 << 20};
    bool backlog_posted = false;
    static constexpr int backlog_per_turn = 256;   // handled before timers, TCP and reading run again
    ClientTable<Peer> clients;
    ReplyPorts reply_ports;             // /reply/port: UDP senders whose replies go to another port
    std::unique_ptr<TcpEndpoint> tcp;
    // /notify subscribers: bounded, so no number of clients can make the server send without end.
    static constexpr std::size_t max_subscribers = 16;
    std::vector<Peer> subscribers;
    asio::steady_timer notify_timer{io};
    // Control-thread record of what the engine has applied, for the queries: timed commands change it
    // when their frame has played (see apply_due_settings), liquids and materials once swapped in.
    std::vector<Command> timed_settings;   // rain, wind, listener, lod changes waiting for their frame
    static constexpr std::size_t max_timed_settings = 4096;
    Liquid applied_liquid;
    MembraneMaterial applied_material;     // the umbrella's, when the scene has one
    TrafficCounters traffic;
    std::chrono::steady_clock::time_point traffic_reported = std::chrono::steady_clock::now();
    protocol::ProtocolContext context;
    SystemdNotifier systemd;
    bool ready = false;
    bool stopping = false;
    bool jack_reported_lost = false;
    std::uint64_t watchdog_frames = 0;
    std::atomic<double> drops_per_second{0.0};   // read by the TCP thread's /status too
    std::uint64_t rate_drops = 0, rate_frames = 0;
    std::uint64_t reconnect_ticks = 0;
    int exit_code = 0;

    // What the audio thread's scene is made of, as the worker last built it. Touched only by jobs on the
    // worker thread, which run one at a time in order, so a liquid change after a surface change builds
    // on that surface, and a refused change leaves it as it was.
    struct SceneSettings {
        MembraneMaterial material;
        Liquid liquid;
    };
    std::shared_ptr<SceneSettings> worker_settings;
    std::unique_ptr<SceneStore> store;
    SceneDescription current_scene;      // as it plays now (what /scene/save writes)
    RendererConfig base_config;          // the stream's (rate, channels, seed), before any scene
    std::map<std::uint16_t, std::deque<std::string>> pending_done;   // per client: scene rebuilds sent, in order

    bool choose_backend();
    bool build_scene();
    void load_scene(const Peer& sender, const std::string& address, const std::string& name);
    void build_and_load(const Peer& sender, const std::string& address,
                        std::function<SceneDescription()> source);
    void edit_scene(const Peer& sender, const std::string& address, const protocol::SceneEdit& edit);
    void save_scene(const Peer& sender, const std::string& address, const std::string& name);
    void use_geometry(const RendererConfig& config, bool has_umbrella);
    void rebuild_scene(const Peer& sender, const std::string& address,
                       std::optional<MembraneMaterial> material, std::optional<Liquid> liquid);
    void on_packet(const unsigned char* data, std::size_t size, const Peer& sender);
    void on_udp_batch(std::span<const UdpEndpoint::Datagram> batch);
    void handle_backlog();
    void reply(const Peer& to, const std::string& address, const std::vector<protocol::OscArgument>& args);
    void reply_status(const Peer& to);
    std::vector<protocol::OscArgument> status_arguments();   // any thread: atomics and constants only
    void answer_query(const Peer& to, const std::string& address, const std::string& name);
    void reply_version(const Peer& to);
    void set_notify(const Peer& to, bool on);
    void set_reply_port(const Peer& sender, int port);
    void notify_subscribers();
    void send_meters();
    void drain_block_trace();
    void apply_setting(const Command& c);
    void apply_due_settings(std::uint64_t frame);
    void forget(const Peer& gone);
    void notice(const std::string& source, const std::string& text);
    void poll();
    void measure_rate();
    void feed_watchdog();
    void shutdown();
};

Daemon::Daemon(const DaemonOptions& options) : state_(std::make_unique<State>()) { state_->options = options; }
Daemon::~Daemon() = default;

bool Daemon::State::choose_backend() {
    const bool want_jack = options.backend != BackendChoice::null;
    if (want_jack) {
        std::string error;
        auto j = JackBackend::open({options.jack_name, options.channels, options.autoconnect}, error);
        if (j) {
            jack = j.get();
            backend = std::move(j);
            return true;
        }
        if (options.backend == BackendChoice::jack) {
            warn("cannot use JACK: " + error);
            return false;
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
        auto nb = std::make_unique<NullBackend>(n, [this] { asio::post(io, [this] { shutdown(); }); });
        null = nb.get();
        backend = std::move(nb);
    } catch (const std::exception& e) {
        warn(e.what());
        return false;
    }
    return true;
}

// Custom umbrella materials by name, for scenes that name one (defined over OSC earlier).
std::optional<MembraneMaterial> find_custom_material(const std::string& name, const void* context) {
    const auto& materials = *static_cast<const std::map<std::string, MembraneMaterial>*>(context);
    const auto found = materials.find(name);
    return found == materials.end() ? std::nullopt : std::optional<MembraneMaterial>(found->second);
}

bool has_umbrella(const SceneDescription& scene) {
    return std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [](const SurfaceDescription& s) { return s.kind == SurfaceKind::umbrella; });
}

// The control thread validates /drop points against its own copy of the umbrella's geometry (the audio
// thread's scene can change at any time).
void Daemon::State::use_geometry(const RendererConfig& config, bool umbrella) {
    geometry = std::make_unique<Canopy>(config.canopy, config.material, 1.0 / config.sample_rate);
    context.surfaces = umbrella ? std::vector<std::string>{"umbrella"} : std::vector<std::string>{};
}

bool Daemon::State::build_scene() {
    base_config.sample_rate = backend->sample_rate();
    base_config.channels = options.channels;
    base_config.seed = options.seed;
    // Shedding detail by measured load makes the output depend on the machine: live playback only. An
    // offline render (null backend, not paced) stays reproducible to the sample.
    base_config.adaptive_lod = !options.fixed_detail && (!null || null->realtime());
    store = std::make_unique<SceneStore>(options.scene_folder ? std::filesystem::path(*options.scene_folder) : SceneStore::default_folder());
    RendererConfig config;
    try {
        current_scene = store->load(options.scene);
        if (options.rain_mm_per_h) current_scene.rain.rate_mm_per_h = *options.rain_mm_per_h;
        config = configure_for_scene(base_config, current_scene, find_custom_material, &custom_materials);
    } catch (const std::exception& e) {
        warn("--scene " + options.scene + ": " + e.what());
        return false;
    }
    bridge = std::make_unique<AudioBridge>(std::make_unique<Renderer>(config), 4096);
    if (options.block_trace) {
        // 16384 records: 22 s of 64-frame callbacks, so the 5 ms poll can fall far behind before one is lost.
        try {
            block_trace = std::make_unique<BlockTraceFile>(*options.block_trace, backend->sample_rate(), options.block_trace_threshold);
        } catch (const std::exception& e) {
            warn(std::string("--block-trace: ") + e.what());
            return false;
        }
        bridge->enable_block_trace(16384);
        say("tracing callbacks over " + std::to_string(static_cast<int>(std::lround(100 * options.block_trace_threshold))) +
            " % of the period to " + *options.block_trace);
    }
    use_geometry(config, has_umbrella(current_scene));
    context.on_surface = [this](const std::string&, double x, double y) { return geometry->locate(x, y).panel >= 0; };
    context.custom_liquid = [this](const std::string& name) -> std::optional<Liquid> {
        const auto found = custom_liquids.find(name);
        return found == custom_liquids.end() ? std::nullopt : std::optional<Liquid>(found->second);
    };
    context.custom_material = [this](const std::string& name) -> std::optional<MembraneMaterial> {
        const auto found = custom_materials.find(name);
        return found == custom_materials.end() ? std::nullopt : std::optional<MembraneMaterial>(found->second);
    };
    worker = std::make_unique<Worker>(io);
    worker_settings = std::make_shared<SceneSettings>(SceneSettings{config.material, config.liquid});
    applied_liquid = config.liquid;
    applied_material = config.material;
    say("scene " + current_scene.name);
    return true;
}

// /scene/load: read (built in or from the folder) and build everything on the worker; the audio thread
// takes it by pointer and rings the old scene out. A file that does not parse changes nothing.
void Daemon::State::load_scene(const Peer& sender, const std::string& address, const std::string& name) {
    build_and_load(sender, address, [name, folder = store->folder()] { return SceneStore(folder).load(name); });
}

// /rain/dsd and /surface/...: the current scene changed, validated here, rebuilt like a loaded one.
void Daemon::State::edit_scene(const Peer& sender, const std::string& address, const protocol::SceneEdit& edit) {
    using Op = protocol::SceneEdit::Op;
    SceneDescription scene = current_scene;
    auto found = std::find_if(scene.surfaces.begin(), scene.surfaces.end(),
                              [&](const SurfaceDescription& f) { return f.name == edit.surface.name; });
    std::string refusal;
    switch (edit.op) {
        case Op::dsd:
            scene.rain.dsd = edit.dsd;
            scene.rain.gamma_mu = edit.mu;
            scene.rain.gamma_lambda_per_mm = edit.lambda;
            break;
        case Op::surface_add:
            if (found != scene.surfaces.end())
                refusal = "a surface named '" + edit.surface.name + "' is already in the scene (/surface/set changes it)";
            else
                scene.surfaces.push_back(edit.surface);
            break;
        case Op::surface_set:
            if (found == scene.surfaces.end())
                refusal = "no surface named '" + edit.surface.name + "' (/surface/add adds one)";
            else if (found->kind == SurfaceKind::umbrella)
                refusal = "the umbrella changes with /material/surface";
            else
                *found = edit.surface;
            break;
        case Op::surface_remove:
            if (found == scene.surfaces.end())
                refusal = "no surface named '" + edit.surface.name + "'";
            else
                scene.surfaces.erase(found);
            break;
        case Op::accuracy: scene.accuracy = edit.accuracy; break;   // configure_for_scene applies it
    }
    if (refusal.empty()) refusal = validate_scene(scene);
    if (!refusal.empty()) {
        reply(sender, "/fail", protocol::fail_arguments(address, refusal));
        return;
    }
    build_and_load(sender, address, [scene] { return scene; });
}

void Daemon::State::build_and_load(const Peer& sender, const std::string& address,
                                   std::function<SceneDescription()> source) {
    const std::uint16_t reply_to = clients.index_of(sender);
    struct Built {
        std::unique_ptr<LoadedScene> loaded;
        SceneDescription scene;
        RendererConfig config;
    };
    worker->submit<std::shared_ptr<Built>>(
        [source = std::move(source), base = base_config, materials = custom_materials, settings = worker_settings] {
            auto built = std::make_shared<Built>();
            built->scene = source();
            RendererConfig c = configure_for_scene(base, built->scene, find_custom_material, &materials);
            c.liquid = settings->liquid;   // the liquid chosen over OSC stays
            if (has_umbrella(built->scene)) {
                const Canopy probe(c.canopy, c.material, 1.0 / c.sample_rate);
                check_live_cost(probe, c.material, c.sample_rate);
            }
            built->loaded = Renderer::make_loaded_scene(c);
            built->config = c;
            settings->material = c.material;
            return built;
        },
        [this, reply_to, address](std::shared_ptr<Built> built) {
            Command c;
            c.kind = CommandKind::load_scene;
            c.object = built->loaded.get();
            c.reply_to = reply_to;
            if (!bridge->send(c)) {
                ++traffic.busy;
                reply(clients.at(reply_to), "/fail", protocol::fail_arguments(address, "busy: command queue full"));
                return;
            }
            built->loaded.release();   // the audio thread owns it now
            current_scene = built->scene;
            applied_material = built->config.material;
            // Timed changes still waiting stay: the renderer keeps its scheduled commands across a load.
            use_geometry(built->config, has_umbrella(current_scene));
            pending_done[reply_to].push_back(address);
            say("scene " + current_scene.name);
        },
        [this, reply_to, address](const std::string& error) {
            reply(clients.at(reply_to), "/fail", protocol::fail_arguments(address, error));
        });
}

// /scene/save: the scene as it plays, written atomically on the worker (disk time stays off the loop).
void Daemon::State::save_scene(const Peer& sender, const std::string& address, const std::string& name) {
    const std::uint16_t reply_to = clients.index_of(sender);
    SceneDescription scene = current_scene;
    scene.name = name;
    worker->submit<std::string>(
        [name, scene, folder = store->folder()] {
            const SceneStore store(folder);
            store.save(name, scene);
            return store.path_of(name).string();
        },
        [this, reply_to, address](const std::string& path) {
            say("saved the scene to " + path);
            reply(clients.at(reply_to), "/done", {protocol::OscArgument::from_string(address)});
        },
        [this, reply_to, address](const std::string& error) {
            reply(clients.at(reply_to), "/fail", protocol::fail_arguments(address, error));
        });
}

// A material or liquid change: the whole scene (canopy, drop pool, collider, far field) is built on the
// worker (a stiff material's stability check and a liquid's calibration take time, and a refusal must not
// disturb the sound), then handed to the audio thread by pointer; the old scene rings out and comes back
// in a `retired` event to be freed here.
void Daemon::State::rebuild_scene(const Peer& sender, const std::string& address,
                                  std::optional<MembraneMaterial> material, std::optional<Liquid> liquid) {
    const std::uint16_t reply_to = clients.index_of(sender);
    const CommandKind kind = material ? CommandKind::swap_surface : CommandKind::swap_liquid;
    worker->submit<std::unique_ptr<UmbrellaScene>>(
        [config = bridge->config(), settings = worker_settings, material, liquid] {
            RendererConfig c = config;
            c.material = material ? *material : settings->material;
            c.liquid = liquid ? *liquid : settings->liquid;
            if (material) {   // refused before anything costly is built (a stiff canopy's templates take long)
                const Canopy probe(c.canopy, *material, 1.0 / c.sample_rate);
                check_live_cost(probe, *material, c.sample_rate);
            }
            auto scene = Renderer::make_scene(c);
            settings->material = c.material;   // only once the scene is built: a refusal changes nothing
            settings->liquid = c.liquid;
            return scene;
        },
        [this, reply_to, address, kind, material, liquid](std::unique_ptr<UmbrellaScene> scene) {
            Command c;
            c.kind = kind;
            c.object = scene.get();
            c.reply_to = reply_to;
            if (bridge->send(c)) {
                scene.release();   // the audio thread owns it now
                // Only now is it in effect (a refused material changed nothing).
                if (material)
                    for (SurfaceDescription& f : current_scene.surfaces)
                        if (f.kind == SurfaceKind::umbrella) f.material = material->name;
                if (material) applied_material = *material;
                if (liquid) applied_liquid = *liquid;
            } else {
                ++traffic.busy;
                reply(clients.at(reply_to), "/fail", protocol::fail_arguments(address, "busy: command queue full"));
            }
        },
        [this, reply_to, address](const std::string& error) {
            reply(clients.at(reply_to), "/fail", protocol::fail_arguments(address, error));
        });
}

void Daemon::State::reply(const Peer& to, const std::string& address, const std::vector<protocol::OscArgument>& args) {
    const auto bytes = protocol::encode_message(address, args);
    // Every reply passes here, so a /reply/port redirect covers them all (/notify's, /notice, /synced).
    if (to.transport == Peer::Transport::udp) udp->send(bytes, reply_ports.destination(to.udp));
    else if (tcp) tcp->send(to.tcp, bytes);
}

// /accuracy with no arguments: the scene's budget (off 0 when none) and the method it chose
// (core/method_choice.hpp): measure, budget, method, sub-steps asked, modes kept (0: all), why.
static std::vector<protocol::OscArgument> accuracy_reply(const SceneDescription& scene) {
    using protocol::OscArgument;
    const AccuracyBudget budget = scene.accuracy.value_or(AccuracyBudget{});
    const MethodSetting setting = scene.accuracy ? choose_method(budget).method.setting : MethodSetting{};
    const std::string why = scene.accuracy ? choose_method(budget).reason : "no budget: the default method";
    return {OscArgument::from_string(scene.accuracy ? accuracy_measure_name(budget.measure) : "off"),
            OscArgument::from_float(static_cast<float>(scene.accuracy ? budget.value : 0.0)),
            OscArgument::from_string(method_label(setting)), OscArgument::from_int(setting.sub_steps),
            OscArgument::from_int(setting.modes), OscArgument::from_string(why)};
}

void Daemon::State::reply_status(const Peer& to) { reply(to, "/status.reply", status_arguments()); }

// /status.reply's fields. Called on the control thread and on the TCP endpoint's thread (which answers
// /status itself, docs/reliability.md "Load"), so it reads only the audio bridge's atomics, the
// backend's atomics and constants, and drops_per_second (atomic).
std::vector<protocol::OscArgument> Daemon::State::status_arguments() {
    using protocol::OscArgument;
    const AudioSnapshot s = bridge->snapshot();
    const std::uint64_t late = s.late_commands;
    return {OscArgument::from_float(static_cast<float>(s.cpu_average_percent)),
           OscArgument::from_float(static_cast<float>(bridge->take_cpu_peak_percent())),
           OscArgument::from_float(static_cast<float>(drops_per_second.load())),
           OscArgument::from_int(s.active_full_drops),   // full tier: lattice drops
           OscArgument::from_int(s.active_impacts),      // template tier: recorded impacts replayed
           OscArgument::from_int(s.active_grains),       // texture tier: noise grains
           OscArgument::from_int(saturate_int32(backend->xruns())),
           OscArgument::from_int(saturate_int32(late)),
           OscArgument::from_float(static_cast<float>(bridge->sample_rate())),
           OscArgument::from_int(backend->block_size()),
           // Seconds, as a float every OSC client reads (Pd 0.53 and sclang 3.13 cannot read int64).
           OscArgument::from_float(static_cast<float>(static_cast<double>(s.frames) / bridge->sample_rate())),
           OscArgument::from_float(static_cast<float>(s.rain_rate_mm_per_h)),
           OscArgument::from_string(backend->name())};
}

// The scene record follows a rain, wind, listener or detail change the engine has (or is about to) apply.
void Daemon::State::apply_setting(const Command& c) { current_scene = protocol::scene_after(current_scene, c); }

// Timed changes whose frame has played, in the order of their frames (ties: as sent).
void Daemon::State::apply_due_settings(std::uint64_t frame) {
    if (timed_settings.empty()) return;
    std::stable_sort(timed_settings.begin(), timed_settings.end(), [](const Command& a, const Command& b) { return a.frame < b.frame; });
    auto due = timed_settings.begin();
    while (due != timed_settings.end() && due->frame <= frame) apply_setting(*due++);
    timed_settings.erase(timed_settings.begin(), due);
}

// ADDRESS with no value -> ADDRESS.reply with what is in effect (docs/PROTOCOL.md, "Queries").
void Daemon::State::answer_query(const Peer& to, const std::string& address, const std::string& name) {
    using protocol::OscArgument;
    auto f = [](double v) { return OscArgument::from_float(static_cast<float>(v)); };
    auto text = [](const std::string& v) { return OscArgument::from_string(v); };
    const std::string reply_address = address + ".reply";
    const SceneDescription& scene = current_scene;
    auto surface = std::find_if(scene.surfaces.begin(), scene.surfaces.end(), [&](const SurfaceDescription& x) { return x.name == name; });
    if (address == "/rain/rate") {
        reply(to, reply_address, {f(scene.rain.rate_mm_per_h)});
    } else if (address == "/rain/wind") {
        reply(to, reply_address, {f(scene.rain.wind_m_per_s), f(degrees(scene.rain.wind_direction_rad)), f(scene.rain.gustiness)});
    } else if (address == "/rain/dsd") {
        reply(to, reply_address, {text(scene.rain.dsd), f(scene.rain.gamma_mu), f(scene.rain.gamma_lambda_per_mm)});
    } else if (address == "/listener") {
        const ListenerDescription& l = scene.listener;
        reply(to, reply_address, {f(l.x_m), f(l.y_m), f(l.z_m), f(degrees(l.facing_rad))});
    } else if (address == "/lod") {
        reply(to, reply_address, {f(scene.lod.budget_percent), OscArgument::from_int(scene.lod.max_full)});
    } else if (address == "/material/liquid") {
        const Liquid& l = applied_liquid;
        reply(to, reply_address, {text(l.name), f(l.density), f(l.surface_tension), f(l.viscosity)});
    } else if (address == "/material/surface") {
        if (surface == scene.surfaces.end() || surface->kind != SurfaceKind::umbrella) {
            reply(to, "/fail", protocol::fail_arguments(address, "no surface named '" + name + "' with a membrane material "
                                                                 "(/surface/set " + name + " tells any surface's material)"));
            return;
        }
        const MembraneMaterial& m = applied_material;
        reply(to, reply_address, {text(name), text(m.name), f(m.areal_density), f(m.tension), f(m.mass_damping), f(m.stiffness_damping)});
    } else if (address == "/surface/set") {
        if (surface == scene.surfaces.end()) {
            reply(to, "/fail", protocol::fail_arguments(address, "no surface named '" + name + "'"));
            return;
        }
        const SurfaceDescription& x = *surface;
        reply(to, reply_address, {text(x.name), text(surface_kind_name(x.kind)), text(x.material), f(x.size_x_m), f(x.size_y_m), f(x.x_m),
                                  f(x.y_m), f(x.z_m)});
    } else if (address == "/surfaces") {
        std::vector<OscArgument> names;
        for (const SurfaceDescription& x : scene.surfaces) names.push_back(text(x.name));
        reply(to, reply_address, names);
    } else if (address == "/scene" || address == "/scene/load") {
        reply(to, reply_address, {text(scene.name)});
    } else if (address == "/accuracy") {
        reply(to, reply_address, accuracy_reply(scene));
    } else if (address == "/reply/port") {
        reply(to, reply_address, {OscArgument::from_int(to.transport == Peer::Transport::udp ? reply_ports.port_of(to.udp) : 0)});
    } else if (address == "/notify") {
        const bool on = std::find(subscribers.begin(), subscribers.end(), to) != subscribers.end();
        reply(to, reply_address, {OscArgument::from_int(on ? 1 : 0)});
    } else {
        // A settable address whose query the table announces but the daemon does not answer: a new
        // address needs its branch above, from the applied state (query_table_test lists them).
        reply(to, "/fail", protocol::fail_arguments(address, "this server cannot answer the query of " + address + " yet"));
    }
}

void Daemon::State::reply_version(const Peer& to) {
    using protocol::OscArgument;
    reply(to, "/version.reply",
          {OscArgument::from_string("ameotod"), OscArgument::from_string(AMEOTO_VERSION),
           OscArgument::from_int(protocol::protocol_version), OscArgument::from_int(udp->local_endpoint().port()),
           OscArgument::from_int(tcp ? tcp->local_endpoint().port() : 0)});
}

// /notify 1|0: scsynth's convention. Subscribing twice is one subscription; leaving when not
// subscribed is not an error (both answer /done, so a patch can send either at any time).
void Daemon::State::set_notify(const Peer& to, bool on) {
    const auto found = std::find(subscribers.begin(), subscribers.end(), to);
    if (on && found == subscribers.end()) {
        if (subscribers.size() >= max_subscribers) {
            reply(to, "/fail", protocol::fail_arguments("/notify", "too many subscribers: at most " + std::to_string(max_subscribers)));
            return;
        }
        subscribers.push_back(to);
    }
    if (!on && found != subscribers.end()) subscribers.erase(found);
    reply(to, "/done", {protocol::OscArgument::from_string("/notify")});
}

// /reply/port PORT: this sender's later replies go to its IP address at PORT (0: its own port again).
// The /done is the first reply to take the new way, so a patch knows its receiver hears the server.
void Daemon::State::set_reply_port(const Peer& sender, int port) {
    if (sender.transport != Peer::Transport::udp) {
        reply(sender, "/fail", protocol::fail_arguments("/reply/port", "a TCP client's replies always come back on its connection"));
        return;
    }
    if (port == 0) {
        reply_ports.restore(sender.udp);
    } else if (!reply_ports.redirect(sender.udp, static_cast<std::uint16_t>(port))) {
        reply(sender, "/fail", protocol::fail_arguments("/reply/port", "too many redirected senders: at most " +
                                                                           std::to_string(ReplyPorts::capacity) +
                                                                           " (/reply/port 0 frees a sender's place)"));
        return;
    }
    clients.index_of(sender);   // known from now on: it gets /notice like any client that sent a command
    reply(sender, "/done", {protocol::OscArgument::from_string("/reply/port")});
}

// A TCP connection that closed: it is no one's subscriber any more.
void Daemon::State::forget(const Peer& gone) { std::erase(subscribers, gone); }

void Daemon::State::notify_subscribers() {
    for (const Peer& p : std::vector<Peer>(subscribers)) reply_status(p);
    notify_timer.expires_after(1s);
    notify_timer.async_wait([this](const boost::system::error_code& ec) {
        if (!ec) notify_subscribers();
    });
}

// --block-trace: every record the audio thread left in the ring; the slow ones go to the file.
void Daemon::State::drain_block_trace() {
    if (!block_trace) return;
    BlockRecord record;
    bool wrote = false;
    while (bridge->block_trace()->pop(record)) wrote |= block_trace->add(record);
    if (wrote) block_trace->flush();
}

// /meter f seconds (audio time at the window's end), i channels, then f peak and f RMS per channel, in dBFS. The newest window only:
// a subscriber wants the level now, and an offline render makes windows faster than anyone reads them.
void Daemon::State::send_meters() {
    MeterWindow newest, w;
    bool any = false;
    while (bridge->take_meter(w)) {
        newest = w;
        any = true;
    }
    if (!any || subscribers.empty()) return;
    std::vector<protocol::OscArgument> args{protocol::OscArgument::from_float(static_cast<float>(static_cast<double>(newest.frame) / backend->sample_rate())),
                                            protocol::OscArgument::from_int(newest.channels)};
    for (int c = 0; c < newest.channels; ++c) {
        args.push_back(protocol::OscArgument::from_float(to_dbfs(newest.peak[c])));
        args.push_back(protocol::OscArgument::from_float(to_dbfs(newest.rms[c])));
    }
    for (const Peer& p : subscribers) reply(p, "/meter", args);
}

// A fault (or its end) that no request asked about: /notice source text to every sender the server knows
// (the last 4096 that sent /status or a command). docs/PROTOCOL.md lists the sources.
void Daemon::State::notice(const std::string& source, const std::string& text) {
    const std::vector<protocol::OscArgument> args{protocol::OscArgument::from_string(source), protocol::OscArgument::from_string(text)};
    for (std::size_t i = 0; i < clients.size(); ++i) reply(clients.at(static_cast<std::uint16_t>(i)), "/notice", args);
}

void Daemon::State::on_packet(const unsigned char* data, std::size_t size, const Peer& sender) {
    const protocol::ReceivedPacket packet = protocol::receive_packet(data, size, context);
    if (packet.failed()) {
        reply(sender, "/fail", protocol::fail_arguments(packet.fail_address, packet.fail_reason));
        return;
    }
    // One clock reading for the whole packet: the messages of a bundle keep their distances to the sample.
    const AudioClock clock = bridge->clock();
    for (const auto& [message, v] : packet.messages) {
        if (!v.ok) {
            if (!protocol::find_address(message.address) && is_reply_address(message.address)) continue;   // never answer a reply
            reply(sender, "/fail", protocol::fail_arguments(message.address, v.reason));
            continue;
        }
        switch (v.request.action) {
            case protocol::Action::status:
                clients.index_of(sender);   // known from now on: it gets /notice (faults) like any client that sent a command
                reply_status(sender);
                break;
            case protocol::Action::quit:
                reply(sender, "/done", {protocol::OscArgument::from_string("/quit")});
                asio::post(io, [this] { shutdown(); });
                break;
            case protocol::Action::set_liquid: {
                const Liquid liquid = *v.request.liquid;
                if (!find_liquid(liquid.name)) custom_liquids[liquid.name] = liquid;
                rebuild_scene(sender, message.address, std::nullopt, liquid);
                break;
            }
            case protocol::Action::set_surface_material: {
                const MembraneMaterial material = *v.request.material;
                if (!membrane_material(material.name)) custom_materials[material.name] = material;
                rebuild_scene(sender, message.address, material, std::nullopt);
                break;
            }
            case protocol::Action::load_scene: load_scene(sender, message.address, v.request.scene_name); break;
            case protocol::Action::save_scene: save_scene(sender, message.address, v.request.scene_name); break;
            case protocol::Action::edit_scene: edit_scene(sender, message.address, v.request.edit); break;
            case protocol::Action::enqueue: {
                Command c = v.request.command;
                // A change must leave a scene that can still be saved and rebuilt (e.g. /listener must not
                // carry the umbrella out of range); the record itself changes once the queue takes it.
                if (protocol::changes_scene(c.kind)) {
                    if (const std::string why = validate_scene(protocol::scene_after(current_scene, c)); !why.empty()) {
                        reply(sender, "/fail", protocol::fail_arguments(message.address, why));
                        break;
                    }
                }
                c.reply_to = clients.index_of(sender);
                if (message.bundled && !message.timetag.immediate()) {
                    c.timed = true;
                    c.frame = frame_at(clock, message.timetag.to_unix_seconds());
                }
                if (!bridge->send(c)) {
                    ++traffic.busy;
                    reply(sender, "/fail", protocol::fail_arguments(message.address, "busy: command queue full"));
                    break;
                }
                // What the queries answer: an untimed change from now on (the audio thread applies it at
                // its next block); a timed one once its frame has played.
                if (!protocol::changes_scene(c.kind)) break;   // rain, wind, listener, lod; not /drop, /sync
                if (!c.timed || c.frame <= bridge->snapshot().frames) apply_setting(c);
                else if (timed_settings.size() < max_timed_settings) timed_settings.push_back(c);
                break;
            }
            case protocol::Action::query: answer_query(sender, v.request.query_address, v.request.query_text); break;
            case protocol::Action::notify: set_notify(sender, v.request.notify_on); break;
            case protocol::Action::version: reply_version(sender); break;
            case protocol::Action::reply_port: set_reply_port(sender, v.request.reply_port); break;
        }
    }
}

// A batch of datagrams read together. Senders outside --allow are dropped before anything else is
// looked at. A cheap query (/status, a query) is answered now, unless its sender has datagrams
// waiting (a sender's messages keep their order); everything else waits its turn in the backlog, so
// the socket is read as fast as the flood comes and the queries in it are not left behind. When the
// backlog is full the datagram is refused /fail busy, by its address, without being decoded.
void Daemon::State::on_udp_batch(std::span<const UdpEndpoint::Datagram> batch) {
    for (const UdpEndpoint::Datagram& d : batch) {
        if (!options.allow.allows(d.sender.address())) {
            ++traffic.refused_senders;   // --allow: no reply, not even /fail
            continue;
        }
        const Peer sender = Peer::over_udp(d.sender);
        if (is_cheap_query(d.data, d.size) && (udp_backlog.empty() || !udp_backlog.holds_from(sender))) {
            on_packet(d.data, d.size, sender);
        } else if (!udp_backlog.push(d.data, d.size, sender)) {
            ++traffic.busy;
            ++traffic.unread;
            const std::string address = protocol::packet_address(d.data, d.size);
            if (address.empty() || is_reply_address(address)) continue;   // never answer a reply (nor what is no message)
            reply(sender, "/fail", protocol::fail_arguments(address, "busy: " + std::to_string(udp_backlog.size()) +
                                                                         " datagrams waiting to be handled"));
        }
    }
    if (!udp_backlog.empty() && !backlog_posted) {
        backlog_posted = true;
        asio::post(io, [this] { handle_backlog(); });
    }
}

// The oldest waiting datagrams, a bounded number per turn: then reading, timers and TCP run again.
void Daemon::State::handle_backlog() {
    backlog_posted = false;
    if (stopping) return;
    udp->hold_replies();
    for (int n = 0; n < backlog_per_turn && !udp_backlog.empty(); ++n) {
        const DatagramBacklog::Waiting& d = udp_backlog.front();
        on_packet(d.data, d.size, d.sender);
        udp_backlog.pop();
    }
    udp->release_replies();
    if (!udp_backlog.empty()) {
        backlog_posted = true;
        asio::post(io, [this] { handle_backlog(); });
    }
}

void Daemon::State::poll() {
    RendererEvent e;
    bool freed_scene = false;
    while (bridge->poll_event(e)) {
        const auto& to = clients.at(e.reply_to);
        if (e.kind == RendererEventKind::retired) {
            // Freed here, never on the audio thread, each as its type.
            if (e.object_type == RetiredObject::scene_surfaces) delete static_cast<SceneSurfaces*>(e.object);
            else if (e.object_type == RetiredObject::loaded_scene) delete static_cast<LoadedScene*>(e.object);
            else delete static_cast<UmbrellaScene*>(e.object);
            freed_scene = true;
        } else if (e.kind == RendererEventKind::swapped) {
            const char* address = e.command == CommandKind::swap_surface  ? "/material/surface"
                                  : e.command == CommandKind::swap_liquid ? "/material/liquid"
                                                                          : "/lod";
            if (e.command == CommandKind::load_scene) {
                // /scene/load, /rain/dsd or a /surface/...: the address waiting for it, in order.
                auto& waiting = pending_done[e.reply_to];
                const std::string what = waiting.empty() ? std::string("/scene/load") : waiting.front();
                if (!waiting.empty()) waiting.pop_front();
                reply(to, "/done", {protocol::OscArgument::from_string(what)});
            } else {
                reply(to, "/done", {protocol::OscArgument::from_string(address)});
            }
        } else if (e.kind == RendererEventKind::synced) {
            reply(to, "/synced", {protocol::OscArgument::from_int(e.id)});
        } else {
            const char* address = e.command == CommandKind::drop        ? "/drop"
                                  : e.command == CommandKind::rain_rate ? "/rain/rate"
                                  : e.command == CommandKind::lod       ? "/lod"
                                                                        : "/sync";
            ++traffic.busy;
            reply(to, "/fail", protocol::fail_arguments(address, "busy: too many scheduled commands"));
        }
    }
    if (freed_scene) return_free_memory();   // RSS follows what is held (memory_return.hpp)
    drain_block_trace();
    const AudioSnapshot s = bridge->snapshot();
    apply_due_settings(s.frames);
    send_meters();
    if (!ready && s.callbacks > 0) {
        ready = true;
        say("running");
        systemd.ready();
        systemd.status("playing on " + backend->name());
    }
    if (null && null->wav()) {
        // Disk full, a write error, the file removed: logged and told over OSC; the audio never waits.
        for (std::string error = null->wav()->take_error(); !error.empty(); error = null->wav()->take_error()) {
            warn(error);
            notice("output", error);
        }
    }
    if (jack) {
        if (jack->server_lost()) {
            if (!jack_reported_lost) {
                warn("the JACK server went away; OSC keeps running, reconnecting when it returns");
                notice("jack", "the JACK server went away; reconnecting when it returns");
                systemd.status("waiting for the JACK server");
                jack_reported_lost = true;
            }
            // Try about every 500 ms (the poll runs every 5 ms).
            if (++reconnect_ticks % 100 == 0) {
                std::string error;
                if (jack->reconnect(error)) {
                    say("JACK server is back: playing again");
                    notice("jack", "the JACK server is back: playing again");
                    systemd.status("playing on jack");
                    jack_reported_lost = false;
                } else if (error.find("Hz") != std::string::npos) {
                    warn(error);
                }
            }
        }
    }
    poll_timer.expires_after(5ms);
    poll_timer.async_wait([this](const boost::system::error_code& ec) {
        if (!ec) poll();
    });
}

void Daemon::State::measure_rate() {
    const AudioSnapshot s = bridge->snapshot();
    if (s.frames > rate_frames) {
        drops_per_second = static_cast<double>(s.drops - rate_drops) * backend->sample_rate() / static_cast<double>(s.frames - rate_frames);
        rate_drops = s.drops;
        rate_frames = s.frames;
    }
    // The load counters, at most every 5 s and only when they changed.
    const auto now = std::chrono::steady_clock::now();
    if (now - traffic_reported >= 5s) {
        if (const auto line = traffic.report_if_changed()) say(*line);
        traffic_reported = now;
    }
    rate_timer.expires_after(1s);
    rate_timer.async_wait([this](const boost::system::error_code& ec) {
        if (!ec) measure_rate();
    });
}

void Daemon::State::feed_watchdog() {
    // WATCHDOG=1 only while the audio cycle advances: a stalled audio thread lets systemd restart us.
    const std::uint64_t frames = bridge->snapshot().frames;
    if (frames != watchdog_frames) systemd.watchdog();
    watchdog_frames = frames;
    watchdog_timer.expires_after(systemd.watchdog_interval());
    watchdog_timer.async_wait([this](const boost::system::error_code& ec) {
        if (!ec) feed_watchdog();
    });
}

void Daemon::State::shutdown() {
    if (stopping) return;   // a signal, /quit and the end of --duration may all ask
    stopping = true;
    systemd.stopping();
    stop_signals.cancel();
    hup_signal.cancel();
    poll_timer.cancel();
    rate_timer.cancel();
    watchdog_timer.cancel();
    notify_timer.cancel();
    if (udp) udp->close();
    if (tcp) tcp->close();
    io.stop();
}

int Daemon::run() {
    State& s = *state_;
    rt::init_probe();
    if (!s.choose_backend()) return 1;
    // The ports first: a port in use is reported at once, not after the scene's seconds of building.
    // Nothing is read from them before io.run(); what arrives meanwhile waits in the kernel's buffers.
    try {
        s.udp = std::make_unique<UdpEndpoint>(s.io, s.options.bind, s.options.port,
                                              [&s](std::span<const UdpEndpoint::Datagram> batch) { s.on_udp_batch(batch); });
    } catch (const std::exception& e) {
        warn("cannot listen on " + s.options.bind + ":" + std::to_string(s.options.port) + ": " + e.what());
        return 1;
    }
    if (s.options.tcp_port) {
        try {
            // The endpoint's callbacks run on its own thread: /status is answered there (from atomics);
            // everything else, and anything that touches the control thread's state, is posted to it.
            s.tcp = std::make_unique<TcpEndpoint>(
                s.options.bind, *s.options.tcp_port, TcpLimits{},
                [&s](const unsigned char* d, std::size_t n, std::uint64_t connection) {
                    if (is_status_request(d, n)) {
                        s.tcp->send_here(connection, protocol::encode_message("/status.reply", s.status_arguments()));
                        asio::post(s.io, [&s, connection] { s.clients.index_of(Peer::over_tcp(connection)); });   // gets /notice
                        return true;
                    }
                    asio::post(s.io, [&s, connection, bytes = std::vector<unsigned char>(d, d + n)] {
                        s.on_packet(bytes.data(), bytes.size(), Peer::over_tcp(connection));
                        s.tcp->handled(connection);   // at most TcpLimits::max_unhandled wait per connection
                    });
                    return false;
                },
                [&s](std::uint64_t connection) { asio::post(s.io, [&s, connection] { s.forget(Peer::over_tcp(connection)); }); });
            s.tcp->set_admit([&s](const boost::asio::ip::address& peer) {
                if (s.options.allow.allows(peer)) return true;
                asio::post(s.io, [&s] { ++s.traffic.refused_senders; });   // --allow: closed at once, no reply
                return false;
            });
        } catch (const std::exception& e) {
            warn("cannot listen on TCP " + s.options.bind + ":" + std::to_string(*s.options.tcp_port) + ": " + e.what());
            return 1;
        }
    }
    if (!s.build_scene()) return 1;
    const auto local = s.udp->local_endpoint();
    if (!local.address().is_loopback())
        warn("listening on " + local.address().to_string() + ", reachable from other machines (--bind)");
    if (s.options.allow.restricts()) say("answering only senders in " + s.options.allow.text() + " (--allow)");
    say("listening on osc.udp://" + local.address().to_string() + ":" + std::to_string(local.port()) + "/");
    if (s.tcp) say("listening on osc.tcp://" + local.address().to_string() + ":" + std::to_string(s.tcp->local_endpoint().port()) + "/");
    if (s.jack) say("backend jack, client " + s.jack->client_name());
    if (s.null) say(s.null->wav() ? "backend null, writing " + s.null->wav()->path() : "backend null, discarding audio");

    s.stop_signals.async_wait([&s](const boost::system::error_code& ec, int) {
        if (!ec) s.shutdown();
    });
    std::function<void()> wait_hup = [&s, &wait_hup] {
        s.hup_signal.async_wait([&s, &wait_hup](const boost::system::error_code& ec, int) {
            if (ec) return;
            if (s.null && s.null->wav()) {
                s.null->wav()->reopen();
                say("SIGHUP: closed the WAV, continuing in a new file");
            }
            wait_hup();
        });
    };
    wait_hup();

    s.backend->start(*s.bridge);
    if (s.null) say("null backend render thread: " + s.null->scheduling());
    if (s.tcp) s.tcp->start();
    s.poll();
    s.measure_rate();
    s.notify_subscribers();
    if (s.systemd.watchdog_interval().count() > 0) s.feed_watchdog();
    s.io.run();

    if (s.tcp) s.tcp->close();   // its thread reads the bridge and the backend: joined before they go
    s.backend->stop();
    if (s.block_trace) {
        s.drain_block_trace();
        s.block_trace->close(s.bridge->block_trace()->lost());
        say("block trace: " + std::to_string(s.block_trace->blocks()) + " callbacks, slow: " +
            std::to_string(s.block_trace->slow_ours()) + " ours, " + std::to_string(s.block_trace->slow_machine()) +
            " the machine's; started late: " + std::to_string(s.block_trace->late()));
    }
    if (s.traffic.busy > 0 || s.traffic.refused_senders > 0) say(s.traffic.report());
    if (s.null && s.null->wav()) say("wrote " + std::to_string(s.null->wav()->frames_written()) + " frames to " + s.null->wav()->path());
    say("stopped");
    return s.exit_code;
}

}  // namespace ameoto
