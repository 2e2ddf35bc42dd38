// SPDX-License-Identifier: GPL-3.0-or-later
// Setting a renderer up for a scene, off the audio thread: the configuration's checks, a scene's fields
// into a RendererConfig (configure_for_scene, apply_output_format), and the objects a scene change
// hands to the audio thread (Renderer::make_scene, Renderer::make_loaded_scene). renderer.hpp declares
// them; the Renderer itself (construction, commands, the sample loop) is renderer.cpp.
#include "engine/render/renderer_setup.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {

namespace renderer_setup {

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

}  // namespace renderer_setup

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
        config.impact = s.impact;
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

std::unique_ptr<LoadedScene> Renderer::make_loaded_scene(const RendererConfig& config, const UmbrellaParts* parts) {
    auto loaded = std::make_unique<LoadedScene>();
    loaded->umbrella = make_scene(config, parts);
    loaded->surfaces = std::make_unique<SceneSurfaces>(config.scene, config.sample_rate, config.channels, config.seed,
                                                       config.full_scale_pa, config.node, config.listener == ListenerStyle::ambix);
    loaded->has_umbrella = umbrella_on_node(config.scene, config.node);
    loaded->rain =
        std::make_unique<RainSpawner>(renderer_setup::rain_config_for(loaded->umbrella->drops.canopy(), config.scene.rain));
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

std::unique_ptr<UmbrellaScene> Renderer::make_scene(const RendererConfig& config, const UmbrellaParts* parts) {
    const DropOnCanopyConfig c = umbrella_config(config);
    return parts ? std::make_unique<UmbrellaScene>(c, *parts) : std::make_unique<UmbrellaScene>(c);
}

std::shared_ptr<const UmbrellaParts> Renderer::make_parts(const RendererConfig& config) {
    return std::make_shared<const UmbrellaParts>(umbrella_config(config));
}

DropOnCanopyConfig Renderer::umbrella_config(const RendererConfig& config) {
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
    c.air_push = config.air_push;
    c.impact = config.impact;   // the templates and texture grains are recorded from this config too
    return c;
}

}  // namespace ameoto
