// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/scene_manager.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "server/log_lines.hpp"
#include "server/scene_store.hpp"

namespace ameoto {
namespace {

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

// Custom umbrella materials by name, for scenes that name one (defined over OSC earlier).
std::optional<MembraneMaterial> find_custom_material(const std::string& name, const void* context) {
    const auto& materials = *static_cast<const std::map<std::string, MembraneMaterial>*>(context);
    const auto found = materials.find(name);
    return found == materials.end() ? std::nullopt : std::optional<MembraneMaterial>(found->second);
}

bool has_umbrella(const SceneDescription& scene) {
    return std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [](const SurfaceDescription& s) { return s.kind == SurfaceKind::umbrella; });
}

}  // namespace

std::optional<FirstScene> read_first_scene(const DaemonOptions& options, double sample_rate, bool live) {
    FirstScene first;
    first.base.sample_rate = sample_rate;
    first.base.channels = options.channels;
    if (options.format) apply_output_format(first.base, *options.format);   // resolve_output_format checked it
    first.base.seed = options.seed;
    first.base.node = options.node;   // kept by every later /scene/load (base_config_)
    // Shedding detail by measured load makes the output depend on the machine: live playback only. An
    // offline render (null backend, not paced) stays reproducible to the sample.
    first.base.adaptive_lod = !options.fixed_detail && live;
    // Binaural: the limiter acts on the decoded ears (server/realtime/binaural_stage.hpp), not on the bus.
    const bool binaural = options.format && options.format->kind == OutputKind::binaural;
    first.base.limiter = options.limiter_on() && !binaural;
    first.level.automatic = options.level_auto;
    first.level.target_lufs = options.target_lufs;
    first.level.limiter = options.limiter_on();
    first.level.full_scale_pa = first.base.full_scale_pa;
    first.folder = options.scene_folder ? std::filesystem::path(*options.scene_folder) : SceneStore::default_folder();
    // A name is a name (built in, or the folder's); anything else parse_options let through is a file's path.
    const bool by_name = is_scene_name(options.scene);
    const std::map<std::string, MembraneMaterial> no_custom_materials;   // none is defined before the first scene
    if (!by_name) {
        try {
            first.scene = SceneStore::read_file(options.scene);
        } catch (const std::exception& e) {
            warn(std::string("--scene: ") + e.what());   // it names the file (and the line and the key)
            return std::nullopt;
        }
    }
    try {
        if (by_name) first.scene = SceneStore(first.folder).load(options.scene);
        if (options.gain_db) first.scene.gain_db = *options.gain_db;
        first.default_rain_mm_per_h = first.scene.rain.rate_mm_per_h;
        const RendererConfig at_default = configure_for_scene(first.base, first.scene, find_custom_material, &no_custom_materials);
        // The umbrella is built once, for the measurement and the stream (umbrella_scene.hpp).
        first.parts = Renderer::make_parts(at_default);
        if (options.level_auto) {   // measured at the scene's own rain, whatever --rain starts it at
            const LevelChoice choice = choose_level(at_default, *first.parts, options.target_lufs);
            first.level.adopt(choice);
        }
        if (options.rain_mm_per_h) first.scene.rain.rate_mm_per_h = *options.rain_mm_per_h;
        first.config = configure_for_scene(first.base, first.scene, find_custom_material, &no_custom_materials);
        first.config.level_gain_db = first.level.level_gain_db;
    } catch (const std::exception& e) {
        warn("--scene " + options.scene + ": " + e.what());
        return std::nullopt;
    }
    return first;
}

SceneManager::SceneManager(boost::asio::io_context& io, const FirstScene& first, AudioBridge& bridge, SceneRecord& record,
                           Replies& replies, TrafficCounters& traffic)
    : bridge_(bridge),
      record_(record),
      replies_(replies),
      traffic_(traffic),
      base_config_(first.base),
      folder_(first.folder),
      worker_settings_(std::make_shared<WorkerSettings>(WorkerSettings{first.config.material, first.config.liquid})),
      level_(first.level),
      worker_(io) {
    use_geometry(first.config, has_umbrella(first.scene));
    context_.ambisonic_order = first.config.listener == ListenerStyle::ambix ? ambix_order(first.config.channels) : 0;
    context_.ears = first.config.listener == ListenerStyle::ears && first.config.channels == 2;
    context_.on_surface = [this](const std::string&, double x, double y) { return geometry_->locate(x, y).panel >= 0; };
    context_.custom_liquid = [this](const std::string& name) -> std::optional<Liquid> {
        const auto found = custom_liquids_.find(name);
        return found == custom_liquids_.end() ? std::nullopt : std::optional<Liquid>(found->second);
    };
    context_.custom_material = [this](const std::string& name) -> std::optional<MembraneMaterial> {
        const auto found = custom_materials_.find(name);
        return found == custom_materials_.end() ? std::nullopt : std::optional<MembraneMaterial>(found->second);
    };
}

// The control thread validates /drop points against its own copy of the umbrella's geometry (the audio
// thread's scene can change at any time).
void SceneManager::use_geometry(const RendererConfig& config, bool umbrella) {
    geometry_ = std::make_unique<Canopy>(config.canopy, config.material, 1.0 / config.sample_rate);
    context_.surfaces = umbrella ? std::vector<std::string>{"umbrella"} : std::vector<std::string>{};
}

void SceneManager::fail(std::uint16_t reply_to, const std::string& address, const std::string& reason) {
    replies_.reply(replies_.peer(reply_to), "/fail", protocol::fail_arguments(address, reason));
}

// /scene/load: read (built in or from the folder) and build everything on the worker; the audio thread
// takes it by pointer and rings the old scene out. A file that does not parse changes nothing.
void SceneManager::load(const Peer& sender, const std::string& address, const std::string& name) {
    build_and_load(sender, address, [name, folder = folder_] { return SceneStore(folder).load(name); }, true);
}

// /rain/dsd and /surface/...: the current scene changed, validated here, rebuilt like a loaded one.
void SceneManager::edit(const Peer& sender, const std::string& address, const protocol::SceneEdit& edit) {
    using Op = protocol::SceneEdit::Op;
    SceneDescription scene = record_.scene();
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
        case Op::air: {   // configure_for_scene applies it
            bool umbrella = false;
            for (SurfaceDescription& s : scene.surfaces)
                if (s.kind == SurfaceKind::umbrella) {
                    s.air = edit.air;
                    umbrella = true;
                }
            if (!umbrella) refusal = "the scene has no umbrella";
            break;
        }
        case Op::impact: {   // configure_for_scene applies it
            bool umbrella = false;
            for (SurfaceDescription& s : scene.surfaces)
                if (s.kind == SurfaceKind::umbrella) {
                    s.impact = edit.impact;
                    umbrella = true;
                }
            if (!umbrella) refusal = "the scene has no umbrella";
            break;
        }
    }
    if (refusal.empty()) refusal = validate_scene(scene);
    if (!refusal.empty()) {
        replies_.reply(sender, "/fail", protocol::fail_arguments(address, refusal));
        return;
    }
    build_and_load(sender, address, [scene] { return scene; }, false);
}

void SceneManager::build_and_load(const Peer& sender, const std::string& address, std::function<SceneDescription()> source,
                                  bool choose) {
    const std::uint16_t reply_to = replies_.know(sender);
    struct Built {
        std::unique_ptr<LoadedScene> loaded;
        SceneDescription scene;
        RendererConfig config;
        std::optional<LevelChoice> level;
        double target_lufs = 0.0;   // the target the level was chosen for
    };
    const bool measure = choose && level_.automatic;
    worker_.submit<std::shared_ptr<Built>>(
        [source = std::move(source), base = base_config_, materials = custom_materials_, settings = worker_settings_, measure,
         target = level_.target_lufs, kept = level_.level_gain_db] {
            auto built = std::make_shared<Built>();
            built->scene = source();
            RendererConfig c = configure_for_scene(base, built->scene, find_custom_material, &materials);
            c.liquid = settings->liquid;   // the liquid chosen over OSC stays
            c.level_gain_db = kept;
            // --level auto: the new scene's own default rain, rendered and measured here on the worker (a
            // second or so of CPU), never on the audio thread.
            // One build of the umbrella for the measurement and the scene (umbrella_scene.hpp).
            const std::shared_ptr<const UmbrellaParts> parts = Renderer::make_parts(c);
            if (measure) {
                built->level = choose_level(c, *parts, target);
                built->target_lufs = target;
                c.level_gain_db = built->level->gain_db;
            }
            if (has_umbrella(built->scene)) {
                const Canopy probe(c.canopy, c.material, 1.0 / c.sample_rate);
                check_live_cost(probe, c.material, c.sample_rate);
            }
            built->loaded = Renderer::make_loaded_scene(c, parts.get());
            built->config = c;
            settings->material = c.material;
            return built;
        },
        [this, reply_to, address](std::shared_ptr<Built> built) {
            Command c;
            c.kind = CommandKind::load_scene;
            c.object = built->loaded.get();
            c.reply_to = reply_to;
            if (take_) take_->note_load(c.object, built->scene, built->config);
            if (!bridge_.send(c)) {
                if (take_) take_->forget(c.object);
                ++traffic_.busy;
                fail(reply_to, address, "busy: command queue full");
                return;
            }
            built->loaded.release();   // the audio thread owns it now
            // Timed changes still waiting stay: the renderer keeps its scheduled commands across a load.
            record_.loaded(built->scene, built->config.material);
            if (built->level) {
                level_.adopt(*built->level);
                // A /loudness that came while the worker measured: the new scene plays at the target in
                // force now, not the one it was measured for (it glides there from its first 50 ms). Found
                // here from the new scene's recording (tens of ms, and only when the two crossed).
                if (level_.target_lufs != built->target_lufs && std::isfinite(level_.measured_lufs)) {
                    Command retarget;
                    retarget.kind = CommandKind::level;
                    retarget.values[0] = retarget_level(*built->level, level_.target_lufs).gain_db;
                    retarget.reply_to = reply_to;
                    if (bridge_.send(retarget)) level_.level_gain_db = retarget.values[0];
                    else ++traffic_.busy;
                }
                say(describe_level(level_, built->scene.name, built->scene.rain.rate_mm_per_h, built->scene.gain_db));
            }
            use_geometry(built->config, has_umbrella(record_.scene()));
            pending_done_[reply_to].push_back(address);
            say("scene " + record_.scene().name);
        },
        [this, reply_to, address](const std::string& error) { fail(reply_to, address, error); });
}

std::string SceneManager::done_address(std::uint16_t reply_to) {
    auto& waiting = pending_done_[reply_to];
    const std::string what = waiting.empty() ? std::string("/scene/load") : waiting.front();
    if (!waiting.empty()) waiting.pop_front();
    return what;
}

// /scene/save: the scene as it plays, written atomically on the worker (disk time stays off the loop).
void SceneManager::save(const Peer& sender, const std::string& address, const std::string& name) {
    const std::uint16_t reply_to = replies_.know(sender);
    SceneDescription scene = record_.scene();
    scene.name = name;
    worker_.submit<std::string>(
        [name, scene, folder = folder_] {
            const SceneStore store(folder);
            store.save(name, scene);
            return store.path_of(name).string();
        },
        [this, reply_to, address](const std::string& path) {
            say("saved the scene to " + path);
            replies_.reply(replies_.peer(reply_to), "/done", {protocol::OscArgument::from_string(address)});
        },
        [this, reply_to, address](const std::string& error) { fail(reply_to, address, error); });
}

void SceneManager::set_loudness(const Peer& sender, const std::string& address, double target_lufs) {
    if (!level_.automatic) {
        replies_.reply(sender, "/fail", protocol::fail_arguments(address, "the level is physical (ameotod --level physical): "
                                                                           "no loudness target; /gain sets a gain"));
        return;
    }
    const std::uint16_t reply_to = replies_.know(sender);
    const double previous = level_.target_lufs;
    // In force at once: the query says it, and a scene whose load is being measured is set to it on arrival.
    level_.target_lufs = target_lufs;
    if (!std::isfinite(level_.measured_lufs) || !level_.recording) {   // a silent scene: its gain stays
        send_level(reply_to, address, level_.level_gain_db, previous);
        return;
    }
    // The gain for the new target, through the limiter, from the recording the choice kept
    // (level_choice.hpp): a few passes of tens of ms, so on the worker, not here.
    worker_.submit<double>([measured = level_.measured(), target_lufs] { return retarget_level(measured, target_lufs).gain_db; },
                           [this, reply_to, address, recording = level_.recording, target_lufs, previous](double gain) {
                               // A scene loaded meanwhile (its own gain is for the target in force) or a
                               // later /loudness: theirs stands.
                               if (level_.recording != recording || level_.target_lufs != target_lufs) return;
                               send_level(reply_to, address, gain, previous);
                           },
                           [this, reply_to, address](const std::string& error) { fail(reply_to, address, error); });
}

// /loudness's gain to the audio thread; a full queue answers /fail and puts the target back.
void SceneManager::send_level(std::uint16_t reply_to, const std::string& address, double gain_db, double previous_target) {
    Command c;
    c.kind = CommandKind::level;
    c.values[0] = gain_db;
    c.reply_to = reply_to;
    if (!bridge_.send(c)) {
        ++traffic_.busy;
        level_.target_lufs = previous_target;
        fail(reply_to, address, "busy: command queue full");
        return;
    }
    level_.level_gain_db = gain_db;
}

void SceneManager::change_material(const Peer& sender, const std::string& address, const MembraneMaterial& material) {
    if (!membrane_material(material.name)) custom_materials_[material.name] = material;
    rebuild(sender, address, material, std::nullopt);
}

void SceneManager::change_liquid(const Peer& sender, const std::string& address, const Liquid& liquid) {
    if (!find_liquid(liquid.name)) custom_liquids_[liquid.name] = liquid;
    rebuild(sender, address, std::nullopt, liquid);
}

// A material or liquid change: the whole scene (canopy, drop pool, collider, far field) is built on the
// worker (a stiff material's stability check and a liquid's calibration take time, and a refusal must not
// disturb the sound), then handed to the audio thread by pointer; the old scene rings out and comes back
// in a `retired` event to be freed on the control thread (audio_events.hpp).
void SceneManager::rebuild(const Peer& sender, const std::string& address, std::optional<MembraneMaterial> material,
                           std::optional<Liquid> liquid) {
    const std::uint16_t reply_to = replies_.know(sender);
    const CommandKind kind = material ? CommandKind::swap_surface : CommandKind::swap_liquid;
    struct Rebuilt {
        std::unique_ptr<UmbrellaScene> scene;
        RendererConfig config;   // what it was built from (a take records its material and liquid)
    };
    worker_.submit<std::shared_ptr<Rebuilt>>(
        [config = bridge_.config(), settings = worker_settings_, material, liquid] {
            RendererConfig c = config;
            c.material = material ? *material : settings->material;
            c.liquid = liquid ? *liquid : settings->liquid;
            if (material) {   // refused before anything costly is built (a stiff canopy's templates take long)
                const Canopy probe(c.canopy, *material, 1.0 / c.sample_rate);
                check_live_cost(probe, *material, c.sample_rate);
            }
            auto rebuilt = std::make_shared<Rebuilt>();
            rebuilt->scene = Renderer::make_scene(c);
            rebuilt->config = c;
            settings->material = c.material;   // only once the scene is built: a refusal changes nothing
            settings->liquid = c.liquid;
            return rebuilt;
        },
        [this, reply_to, address, kind, material, liquid](std::shared_ptr<Rebuilt> rebuilt) {
            Command c;
            c.kind = kind;
            c.object = rebuilt->scene.get();
            c.reply_to = reply_to;
            if (take_) take_->note_swap(c.object, kind, rebuilt->config);
            if (bridge_.send(c)) {
                rebuilt->scene.release();   // the audio thread owns it now
                // Only now is it in effect (a refused material changed nothing).
                if (material) record_.material_changed(*material);
                if (liquid) record_.liquid_changed(*liquid);
            } else {
                if (take_) take_->forget(c.object);
                ++traffic_.busy;
                fail(reply_to, address, "busy: command queue full");
            }
        },
        [this, reply_to, address](const std::string& error) { fail(reply_to, address, error); });
}

}  // namespace ameoto
