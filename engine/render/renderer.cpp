// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/renderer.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/physical_constants.hpp"
#include "engine/render/renderer_setup.hpp"

namespace ameoto {

// The configuration's checks and the scene building functions are in renderer_setup.cpp; where each drop
// goes (the lattice pool, a template, a texture grain) is in renderer_drops.cpp.
using renderer_setup::checked;
using renderer_setup::output_config;
using renderer_setup::rain_config_for;

namespace {

// x times a gain, exact when the gain is 1 (the physical samples stay bit for bit).
inline float scaled(float x, double gain) { return gain == 1.0 ? x : static_cast<float>(x * gain); }

}  // namespace

Renderer::Renderer(const RendererConfig& config, const UmbrellaParts* parts)
    : config_(checked(config)),
      dt_(1.0 / config.sample_rate),
      rng_(config.seed),
      scene_(make_scene(config_, parts).release()),
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
    prior_frames_ = 0;
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
    prior_frames_ = 0;
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

void Renderer::price_lattice_drops(int frames) {
    prior_frames_ = frames;
    const ImpactTemplateTable& t = scene_->templates;
    const int sizes = static_cast<int>(t.diameters_m.size());
    if (!has_umbrella_ || frames <= 0 || sizes == 0) return governor_.set_lattice_prior(0.0);
    const double period = frames * dt_;
    if (sizes > LodGovernor::max_prior_sizes) return governor_.set_lattice_prior(t.worst_cpu_s(frames) / period);
    for (int k = 0; k < sizes; ++k) prior_events_[static_cast<std::size_t>(k)] = t.worst_cpu_s(frames, k) / period;
    governor_.set_lattice_prior(t.diameters_m.data(), prior_events_.data(), sizes);
}

void Renderer::process(int frames, float* const* outputs) {
    // Live: before a lattice drop can be admitted, the governor knows what one cost in a block this long
    // when its templates were recorded, on this machine.
    if (config_.adaptive_lod && frames != prior_frames_) price_lattice_drops(frames);
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
