// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/drop.hpp"

namespace ameoto {

namespace {

// x times a gain, exact when the gain is 1 (the physical samples stay bit for bit).
inline float scaled(float x, double gain) { return gain == 1.0 ? x : static_cast<float>(x * gain); }

RainSpawner::Config rain_config_for(const Canopy& canopy, const RainDescription& rain) {
    RainSpawner::Config rc;
    rc.area_m2 = canopy.area();
    rc.dsd = drop_size_distribution_for(rain);
    return rc;
}

const RendererConfig& checked(const RendererConfig& config) {
    if (config.channels < 1 || config.channels > Renderer::max_channels)
        throw std::invalid_argument("channels must be 1 to 16");
    if (config.listener == ListenerStyle::ambix && ambix_order(config.channels) < 1)
        throw std::invalid_argument("an Ambisonic bus has 4, 9 or 16 channels (orders 1 to 3)");
    if (!(config.sample_rate >= 8000.0 && config.sample_rate <= 384000.0))
        throw std::invalid_argument("sample rate must be 8000 to 384000 Hz");
    if (config.node < 0 || config.node > max_scene_nodes) throw std::invalid_argument("node must be 0 (the whole scene) to 16");
    if (config.full_drops < 0 || config.full_drops > Renderer::max_full_drops)
        throw std::invalid_argument("full drops must be 0 to 64");
    if (!(config.lod_budget >= 0.01 && config.lod_budget <= 0.95)) throw std::invalid_argument("lod budget must be 0.01 to 0.95");
    return config;
}

OutputStageConfig output_config(const RendererConfig& config) {
    OutputStageConfig o;
    o.channels = config.channels;
    o.sample_rate = config.sample_rate;
    o.gain_db = config.gain_db;
    o.limiter = config.limiter;
    return o;
}

}  // namespace

void apply_output_format(RendererConfig& config, const OutputFormat& format) {
    switch (format.kind) {
        case OutputKind::stereo: config.listener = ListenerStyle::panned; break;
        case OutputKind::ears: config.listener = ListenerStyle::ears; break;
        case OutputKind::ring: config.listener = ListenerStyle::panned; break;
        case OutputKind::ambix: config.listener = ListenerStyle::ambix; break;
        case OutputKind::binaural:
            // The renderer makes the third-order bus; the caller decodes it to two ears (BinauralDecoder).
            config.listener = ListenerStyle::ambix;
            config.channels = ambix_channels(format.order);
            return;
    }
    config.channels = format.channels;
}

bool umbrella_on_node(const SceneDescription& scene, int node) {
    return std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [node](const SurfaceDescription& s) {
        return s.kind == SurfaceKind::umbrella && (node == 0 || s.node == node);
    });
}

RendererConfig configure_for_scene(RendererConfig config, const SceneDescription& scene, MaterialResolver material,
                                   const void* context) {
    if (const std::string why = validate_scene(scene); !why.empty()) throw std::invalid_argument(why);
    config.scene = scene;
    config.rain_rate_mm_per_h = scene.rain.rate_mm_per_h;
    config.gain_db = scene.gain_db;
    config.lod_budget = scene.lod.budget_percent / 100.0;
    config.full_drops = std::min(scene.lod.max_full, Renderer::max_full_drops);
    // The accuracy knob: the cheapest measured method within the budget; none: the default method.
    config.canopy_network = scene.accuracy ? network_options_for(choose_method(*scene.accuracy).method.setting) : NetworkOptions{};
    for (const SurfaceDescription& s : scene.surfaces) {
        if (s.kind != SurfaceKind::umbrella) continue;
        std::optional<MembraneMaterial> m = membrane_material(s.material);
        if (!m && material) m = material(s.material, context);
        if (!m) throw std::invalid_argument("surface '" + s.name + "': no umbrella material named '" + s.material + "'");
        config.material = *m;
        config.air = s.air;
        config.canopy.panels = s.panels;
        config.canopy.radius_m = s.size_x_m / 2.0;
        // The umbrella is held over the listener: the far field hears it from under its shaft.
        const double below = s.z_m - scene.listener.z_m;
        if (std::abs(s.x_m - scene.listener.x_m) > 1e-9 || std::abs(s.y_m - scene.listener.y_m) > 1e-9 || !(below > 0.05))
            throw std::invalid_argument("surface '" + s.name +
                                        "': the umbrella is held over the listener: its x and y must be the listener's and "
                                        "its z at least 0.05 m above the listener's");
        config.listener_below_m = below;
    }
    return config;
}

std::unique_ptr<LoadedScene> Renderer::make_loaded_scene(const RendererConfig& config) {
    auto loaded = std::make_unique<LoadedScene>();
    loaded->umbrella = make_scene(config);
    loaded->surfaces = std::make_unique<SceneSurfaces>(config.scene, config.sample_rate, config.channels, config.seed,
                                                       config.full_scale_pa, config.node, config.listener == ListenerStyle::ambix);
    loaded->has_umbrella = umbrella_on_node(config.scene, config.node);
    loaded->rain = std::make_unique<RainSpawner>(rain_config_for(loaded->umbrella->drops.canopy(), config.scene.rain));
    loaded->rain_rate_mm_per_h = config.rain_rate_mm_per_h;
    loaded->wind_m_per_s = config.scene.rain.wind_m_per_s;
    loaded->wind_direction_rad = config.scene.rain.wind_direction_rad;
    loaded->gustiness = config.scene.rain.gustiness;
    loaded->lod_budget = config.lod_budget;
    loaded->max_full = config.full_drops;
    loaded->level_gain_db = config.level_gain_db;
    loaded->gain_db = config.gain_db;
    return loaded;
}

std::unique_ptr<UmbrellaScene> Renderer::make_scene(const RendererConfig& config) {
    DropOnCanopyConfig c;
    c.sample_rate = config.sample_rate;
    c.material = config.material;
    c.liquid = config.liquid;
    c.geometry = config.canopy;
    c.output = SceneOutput::far_field;
    c.channels = config.channels;
    c.listener = config.listener;
    c.capacity = max_full_drops;  // the governor keeps to its own limit within it (/lod)
    c.max_diameter = 8e-3;        // the protocol's largest /drop
    c.gap_m = 0.0;                // touching the cap: a /drop strikes at its sample (within a sample or two)
    c.listener_below_m = config.listener_below_m;
    c.full_scale_pa = config.full_scale_pa;
    c.retire_below_m = -1.0;      // m: a drop retires when all its pieces have fallen a metre below the cap
    // Model no more than is heard: a drop is followed for 0.5 s, through its impact, its splash and the
    // pieces' first strikes back onto the membrane (the loud part is over in a few ms, drop_on_canopy_test);
    // then its pieces are retired and the membrane rings on alone. (The elastic collisions of the seed let
    // pieces bounce on the cap for seconds; each one awake costs the audio thread.)
    c.max_lifetime_s = 0.5;
    c.guard_interval = 0;         // the renderer runs the guard after every block
    c.network = config.canopy_network;
    c.settle = config.settle;
    c.air = config.air;
    return std::make_unique<UmbrellaScene>(c);
}

Renderer::Renderer(const RendererConfig& config)
    : config_(checked(config)),
      dt_(1.0 / config.sample_rate),
      rng_(config.seed),
      scene_(make_scene(config_).release()),
      rain_(new RainSpawner(rain_config_for(scene_->drops.canopy(), config_.scene.rain))),
      governor_(LodSettings{.budget = config_.lod_budget,
                            .max_full = config_.full_drops,
                            .full_level_db = config_.lod_full_level_db,
                            .texture_margin_db = config_.lod_texture_margin_db}),
      grains_(std::make_unique<TextureGrains>(scene_->texture, config_.sample_rate)),
      grain_noise_(config.seed ^ 0x9E3779B97F4A7C15ull),
      output_(output_config(config_)) {
    set_level_db(config_.level_gain_db, false);
    surfaces_ = new SceneSurfaces(config_.scene, config_.sample_rate, config_.channels, config_.seed, config_.full_scale_pa,
                                  config_.node, ambisonic());
    if (ambisonic()) {
        rotation_from_ = rotation_to_ = AmbixRotation::identity(ambix_order(config_.channels));
        facing_turn_.reset(ambix_order(config_.channels), config_.scene.listener.facing_rad);
        encode_grains(scene_->drops.canopy());
    }
    has_umbrella_ = umbrella_on_node(config_.scene, config_.node);
    rain_->set_rate_now(has_umbrella_ ? config.rain_rate_mm_per_h : 0.0);
    wind_ = Wind(Wind::Config{.turbulence_intensity = config_.scene.rain.gustiness});
    wind_.set_now(config_.scene.rain.wind_m_per_s, config_.scene.rain.wind_direction_rad);
    surfaces_->set_rate_now(config.rain_rate_mm_per_h);
    rain_rate_ = config.rain_rate_mm_per_h;
}

Renderer::~Renderer() {
    // Runs on the control thread once audio has stopped: free everything still owned, including scenes
    // waiting in the pending list.
    for (int i = 0; i < pending_count_; ++i) {
        const Command& c = pending_[static_cast<std::size_t>(i)];
        if (c.kind == CommandKind::swap_surface || c.kind == CommandKind::swap_liquid) delete static_cast<UmbrellaScene*>(c.object);
        if (c.kind == CommandKind::load_scene) delete static_cast<LoadedScene*>(c.object);
        if (c.kind == CommandKind::orientation) delete static_cast<AmbixRotation*>(c.object);
    }
    for (AmbixRotation* r : unreturned_) delete r;
    delete fading_;
    delete scene_;
    delete fading_surfaces_;
    delete surfaces_;
    delete rain_;
}

bool Renderer::push_event_checked(const RendererEvent& event) {
    if (event_count_ == event_capacity) return false;   // the control thread is far behind
    events_[static_cast<std::size_t>((event_read_ + event_count_) % event_capacity)] = event;
    ++event_count_;
    return true;
}

bool Renderer::poll_event(RendererEvent& event) {
    if (event_count_ == 0) return false;
    event = events_[static_cast<std::size_t>(event_read_)];
    event_read_ = (event_read_ + 1) % event_capacity;
    --event_count_;
    return true;
}

bool Renderer::retire(void* object, RetiredObject type) {
    RendererEvent e;
    e.kind = RendererEventKind::retired;
    e.object = object;
    e.object_type = type;
    return push_event_checked(e);
}

void Renderer::swap_scene(const Command& c) {
    auto* incoming = static_cast<UmbrellaScene*>(c.object);
    if (!incoming || incoming->drops.canopy().panel_count() != scene_->drops.canopy().panel_count() ||
        incoming->drops.channels() != scene_->drops.channels() ||
        incoming->templates.diameters_m != scene_->templates.diameters_m) {
        // Only a scene of the same shape can take over (the sounding templates address its panels and
        // its table's sizes, the outputs its channels); a mismatch goes straight back to be freed.
        retire(incoming, RetiredObject::umbrella_scene);
        return;
    }
    if (fading_) retire(fading_, RetiredObject::umbrella_scene);   // a change during a fade
    if (fading_surfaces_) retire(fading_surfaces_, RetiredObject::scene_surfaces);
    fading_surfaces_ = nullptr;
    fading_ = scene_;
    fading_has_umbrella_ = has_umbrella_;
    fading_level_ = level_;   // a material or liquid change keeps the scene's level gain
    fade_left_ = static_cast<int>(0.5 / dt_);
    scene_ = incoming;
    grains_->set_calibration(scene_->texture);
    if (ambisonic()) encode_grains(scene_->drops.canopy());
    hand_over_listener();
    push_event({RendererEventKind::swapped, c.kind, c.reply_to, c.id});
}

void Renderer::set_wind(double speed, double direction, double gustiness) {
    // A new gust intensity restarts the gust process (a Wind is plain data: no allocation); speed and
    // direction ramp from where they are (wind.hpp).
    const double mean = wind_.mean_speed(), heading = wind_.direction();
    wind_ = Wind(Wind::Config{.turbulence_intensity = gustiness});
    wind_.set_now(mean, heading);
    wind_.set_speed(speed);
    wind_.set_direction(direction);
}

// The scene's level gain: at once (construction) or over 50 ms, in equal dB steps (no click).
void Renderer::set_level_db(double db, bool ramp) {
    level_db_ = db;
    level_target_ = std::pow(10.0, db / 20.0);
    const int frames = std::max(1, static_cast<int>(std::lround(0.05 / dt_)));
    if (!ramp || level_target_ == level_) {
        level_ = level_target_;
        level_ramp_left_ = 0;
        return;
    }
    level_step_ = std::pow(level_target_ / level_, 1.0 / frames);
    level_ramp_left_ = frames;
}

void Renderer::load_scene(const Command& c) {
    auto* loaded = static_cast<LoadedScene*>(c.object);
    if (!loaded || !loaded->umbrella || !loaded->surfaces || loaded->umbrella->drops.channels() != config_.channels ||
        loaded->umbrella->templates.diameters_m != scene_->templates.diameters_m) {
        retire(loaded, RetiredObject::loaded_scene);   // not for this stream: back unused (the caller checks first)
        return;
    }
    // The old umbrella and surfaces ring out together for 0.5 s; the envelope goes straight back.
    if (fading_) retire(fading_, RetiredObject::umbrella_scene);
    if (fading_surfaces_) retire(fading_surfaces_, RetiredObject::scene_surfaces);
    fading_ = scene_;
    fading_surfaces_ = surfaces_;
    fading_has_umbrella_ = has_umbrella_;
    fading_level_ = level_;
    fade_left_ = static_cast<int>(0.5 / dt_);
    // The new scene starts silent: its level gain can start at once. The texture grains still sounding
    // (a few ms) are the old scene's; the ramp keeps a much larger new gain from lifting them abruptly.
    set_level_db(loaded->level_gain_db, true);
    output_.set_gain_db(loaded->gain_db);
    scene_ = loaded->umbrella.release();
    surfaces_ = loaded->surfaces.release();
    has_umbrella_ = loaded->has_umbrella;
    grains_->set_calibration(scene_->texture);
    if (ambisonic()) encode_grains(scene_->drops.canopy());
    hand_over_listener();
    rain_rate_ = loaded->rain_rate_mm_per_h;
    // The new rain spawner takes over; the old one goes back in the envelope (no allocation here).
    RainSpawner* old_rain = rain_;
    rain_ = loaded->rain.release();
    loaded->rain.reset(old_rain);
    rain_->set_rate_now(has_umbrella_ ? old_rain->rate() : 0.0);
    rain_->set_rate(has_umbrella_ ? rain_rate_ : 0.0);
    set_wind(loaded->wind_m_per_s, loaded->wind_direction_rad, loaded->gustiness);
    surfaces_->set_rate_now(rain_rate_);
    LodSettings lod = governor_.settings();
    lod.budget = loaded->lod_budget;
    lod.max_full = loaded->max_full;
    governor_.set_settings(lod);
    retire(loaded, RetiredObject::loaded_scene);
    push_event({RendererEventKind::swapped, c.kind, c.reply_to, c.id});
}

void Renderer::schedule(const Command& command) {
    Command c = command;
    if (!c.timed || c.frame < frame_) {
        if (c.timed) ++stats_.late_commands;
        c.frame = frame_;   // due now: the first sample of the next block
    }
    if (pending_count_ == pending_capacity) {
        ++stats_.busy_commands;
        push_event({RendererEventKind::busy, c.kind, c.reply_to, c.id});
        return;
    }
    // Insertion keeps the list sorted by frame and first-come-first-served among equal frames.
    int i = pending_count_;
    while (i > 0 && pending_[static_cast<std::size_t>(i - 1)].frame > c.frame) {
        pending_[static_cast<std::size_t>(i)] = pending_[static_cast<std::size_t>(i - 1)];
        --i;
    }
    pending_[static_cast<std::size_t>(i)] = c;
    ++pending_count_;
}

void Renderer::start_impact(double diameter_m, double speed_m_per_s, double x, double y) {
    const CanopyHit hit = scene_->drops.canopy().locate(x, y);
    if (hit.panel < 0) return;
    ++stats_.drops;
    if (!impacts_.add(hit, scene_->templates, diameter_m, speed_m_per_s, scene_->drops.config().liquid.density))
        ++stats_.impacts_dropped;
}

void Renderer::start_rain_drop(double diameter, Point2 at) {
    DropOnCanopy& drops = scene_->drops;
    // The listener is under the shaft: the drop's distance to it, from its point on the cap.
    const double height = drops.canopy().rest_height(at.x, at.y) + config_.listener_below_m;
    const double distance = std::sqrt(at.x * at.x + at.y * at.y + height * height);
    const double density = drops.config().liquid.density;
    // The wind adds horizontal speed: the membrane feels its component along the normal there (wind.hpp).
    const Vec3 normal = drops.canopy().surface_normal(at.x, at.y);
    const double still = arrival_speed(diameter, density);
    const double speed = std::max(0.1 * still, wind_.impact(diameter, normal).normal_speed * std::sqrt(density / constants::water_density));
    const int full_active = static_cast<int>(drops.pool().active().size());
    ++block_drops_;
    switch (governor_.choose(diameter, speed, distance, full_active)) {
        case LodTier::full:
            if (!drops.full() && drops.drop(diameter, speed, at.x, at.y)) {
                ++stats_.drops;
                ++stats_.rain_tiers.full;
                return;
            }
            [[fallthrough]];   // the pool filled up meanwhile (a /drop in the same sample): a template
        case LodTier::template_:
            ++stats_.rain_tiers.template_;
            start_impact(diameter, speed, at.x, at.y);
            return;
        case LodTier::texture:
            ++stats_.drops;
            ++stats_.rain_tiers.texture;
            if (!grains_->add(diameter, speed, density, grain_azimuth(at, height), ambisonic() ? grain_ring : config_.channels, grain_noise_))
                ++stats_.grains_dropped;
            return;
    }
}

void Renderer::start_drop(const Command& c) {
    const double diameter = c.values[0], speed = c.values[1], x = c.values[2], y = c.values[3];
    DropOnCanopy& drops = scene_->drops;
    if (!has_umbrella_) return;   // the protocol refuses /drop on a scene without one
    if (static_cast<int>(drops.pool().active().size()) < governor_.settings().max_full && !drops.full()) {
        if (drops.drop(diameter, speed, x, y)) {
            ++stats_.drops;
            ++stats_.full_drops;
        }
        return;   // false: off the canopy or not a drop (the protocol has already refused those)
    }
    // The pool is full: the drop is still heard, as a template.
    if (drops.canopy().locate(x, y).panel < 0) return;
    ++stats_.drop_fallbacks;
    start_impact(diameter, speed, x, y);
}

void Renderer::apply(const Command& c) {
    switch (c.kind) {
        case CommandKind::drop: start_drop(c); break;
        case CommandKind::rain_rate:
            rain_rate_ = c.values[0];
            if (has_umbrella_) rain_->set_rate(rain_rate_);
            surfaces_->set_rate(rain_rate_);
            break;
        case CommandKind::load_scene: load_scene(c); break;
        case CommandKind::wind: set_wind(c.values[0], c.values[1], c.values[2]); break;
        case CommandKind::listener: move_listener(c); break;
        case CommandKind::sync: push_event({RendererEventKind::synced, c.kind, c.reply_to, c.id}); break;
        case CommandKind::swap_surface:
        case CommandKind::swap_liquid: swap_scene(c); break;
        case CommandKind::gain: output_.set_gain_db(c.values[0]); break;
        case CommandKind::level: set_level_db(c.values[0], true); break;
        case CommandKind::orientation: set_orientation(c); break;
        case CommandKind::lod: {
            LodSettings s = governor_.settings();
            s.budget = c.values[0];
            s.max_full = static_cast<int>(c.values[1]);
            governor_.set_settings(s);
            push_event({RendererEventKind::swapped, c.kind, c.reply_to, c.id});
            break;
        }
    }
}

void Renderer::render_sample(float* const* outputs, int offset) {
    const int arrivals = rain_->advance(dt_, rng_);
    for (int a = 0; a < arrivals; ++a) {
        const double d = rain_->sample_diameter_m(rng_);
        start_rain_drop(d, scene_->drops.canopy().sample_point(rng_));
    }
    // The recorded force is along the membrane's normal as the collider gave it (a drop pushes down).
    Canopy& surface = scene_->drops.surface();
    impacts_.emit(scene_->templates, [&surface](CanopyHit hit, double force) { surface.apply_force(hit, force); });
    float frame[max_channels] = {};
    const int channels = config_.channels;
    // Ambisonics with the body turned: the surfaces on their world bus, turned by the facing into the
    // body bus (renderer.hpp, "Ambisonics"); otherwise straight into the frame.
    const bool turn_world = facing_turn_.active();
    float world[max_channels] = {};
    if (turn_world) facing_turn_.step();
    if (has_umbrella_) scene_->drops.process_frame(frame);
    surfaces_->render(turn_world ? world : frame, wind_);
    if (turn_world) facing_turn_.add_turned(world, frame);
    if (level_ramp_left_ > 0) {
        level_ *= level_step_;
        if (--level_ramp_left_ == 0) level_ = level_target_;
    }
    if (!fading_)
        for (int ch = 0; ch < channels; ++ch) frame[ch] = scaled(frame[ch], level_);
    if (fading_) {
        float old[max_channels] = {};
        if (fading_has_umbrella_) fading_->drops.process_frame(old);
        if (fading_surfaces_) {
            float old_world[max_channels] = {};
            fading_surfaces_->render(turn_world ? old_world : old, wind_);
            if (turn_world) facing_turn_.add_turned(old_world, old);
        }
        for (int ch = 0; ch < channels; ++ch) frame[ch] = scaled(frame[ch], level_) + scaled(old[ch], fading_level_);
        if (--fade_left_ <= 0) {
            // If the event list is full they ring on and are handed back at a later sample.
            if (fading_surfaces_ && retire(fading_surfaces_, RetiredObject::scene_surfaces)) fading_surfaces_ = nullptr;
            if (!fading_surfaces_ && retire(fading_, RetiredObject::umbrella_scene)) fading_ = nullptr;
        }
    }
    if (ambisonic()) {
        // The bed over its virtual ring, each direction encoded (renderer.hpp, "Ambisonics").
        float ring[grain_ring] = {};
        grains_->render(ring, grain_ring, grain_noise_);
        for (int v = 0; v < grain_ring; ++v) {
            if (ring[v] == 0.0f) continue;
            const double x = ring[v] * level_;
            const auto& e = grain_encoding_[static_cast<std::size_t>(v)];
            for (int ch = 0; ch < channels; ++ch) frame[ch] += static_cast<float>(e[static_cast<std::size_t>(ch)] * x);
        }
    } else if (level_ == 1.0) {
        grains_->render(frame, channels, grain_noise_);   // the physical sum, in the order it always had
    } else {
        float grains[max_channels] = {};
        grains_->render(grains, channels, grain_noise_);
        for (int ch = 0; ch < channels; ++ch) frame[ch] += scaled(grains[ch], level_);
    }
    if (rotating_) rotate(frame);
    output_.process_frame(frame);
    for (int ch = 0; ch < channels; ++ch) outputs[ch][offset] = frame[ch];
    // The governor is told the drop rate every governor_period samples, counted on the sample clock, so
    // its choices do not depend on the caller's block size (and, live only, the load last measured).
    if (++governor_samples_ == governor_period) {
        wind_.advance(governor_period * dt_, grain_noise_);   // the wind's control rate: 64 samples
        governor_.end_block(config_.adaptive_lod ? measured_load_ : 0.0, block_drops_, governor_period * dt_);
        governor_samples_ = 0;
        block_drops_ = 0;
    }
}

void Renderer::set_measured_load(double load) {
    measured_load_ = load;
    if (config_.adaptive_lod) governor_.observe_load(load, last_activity_, last_block_seconds_);
}

void Renderer::process(int frames, float* const* outputs) {
    const DropPool& pool = scene_->drops.pool();
    const DropPoolStats before = pool.stats();
    const DropPool* pool_before = &pool;
    const int awake_before = static_cast<int>(pool.active().size());
    const RendererStats stats_before = stats_;
    int commands = 0;
    for (int n = 0; n < frames; ++n) {
        const std::uint64_t now = frame_ + static_cast<std::uint64_t>(n);
        // Apply every command due at this sample, in order.
        int applied = 0;
        while (applied < pending_count_ && pending_[static_cast<std::size_t>(applied)].frame <= now)
            apply(pending_[static_cast<std::size_t>(applied++)]);
        commands += applied;
        if (applied > 0) {
            std::copy(pending_.begin() + applied, pending_.begin() + pending_count_, pending_.begin());
            pending_count_ -= applied;
        }
        render_sample(outputs, n);
    }
    frame_ += static_cast<std::uint64_t>(frames);
    for (AmbixRotation*& slot : unreturned_)   // rotations the event list could not take before
        if (slot && retire(slot, RetiredObject::rotation)) slot = nullptr;
    // Runtime guard (core/stability.hpp): a panel whose state went non-finite or whose energy ran away is
    // reset and counted, never left to explode.
    stats_.body_resets += static_cast<std::uint64_t>(scene_->drops.guard());
    if (fading_) stats_.body_resets += static_cast<std::uint64_t>(fading_->drops.guard());
    stats_.active_impacts = impacts_.active();
    stats_.active_full_drops = static_cast<int>(scene_->drops.pool().active().size());
    // For the governor's price of a lattice drop (set_measured_load): a spawn or a break in this block.
    const DropPoolStats& after = scene_->drops.pool().stats();
    last_activity_.awake = std::max(awake_before, stats_.active_full_drops);
    last_activity_.event = pool_before != &scene_->drops.pool() || after.spawned != before.spawned ||
                           after.link_breaks != before.link_breaks;
    last_block_seconds_ = frames * dt_;
    stats_.active_grains = grains_->active();
    stats_.detail = governor_.detail();
    stats_.rain_tiers.priced_out = governor_.counts().priced_out;
    stats_.rain_rate_mm_per_h = has_umbrella_ ? rain_->rate() : rain_rate_;
    stats_.surface_drops = surfaces_->drops();
    stats_.clipped_samples = output_.clipped();
    // The block's record (last_block): counters' differences, so the steady path pays a few subtractions.
    const bool same_pool = pool_before == &scene_->drops.pool();
    BlockActivity& b = last_block_;
    b.commands = commands;
    b.lattice_spawned = same_pool ? static_cast<int>(after.spawned - before.spawned) : static_cast<int>(after.spawned);
    b.lattice_awake = last_activity_.awake;
    b.link_breaks = same_pool ? after.link_breaks - before.link_breaks : after.link_breaks;
    b.full_rain = static_cast<int>(stats_.rain_tiers.full - stats_before.rain_tiers.full);
    b.template_impacts = static_cast<int>(stats_.rain_tiers.template_ - stats_before.rain_tiers.template_ +
                                          stats_.drop_fallbacks - stats_before.drop_fallbacks);
    b.texture_grains = static_cast<int>(stats_.rain_tiers.texture - stats_before.rain_tiers.texture);
    b.priced_out = static_cast<int>(stats_.rain_tiers.priced_out - stats_before.rain_tiers.priced_out);
    b.detail = stats_.detail;
    b.scene_changed = !same_pool;
}

}  // namespace ameoto
