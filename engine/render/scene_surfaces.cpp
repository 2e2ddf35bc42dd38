// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/scene_surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/models/drop.hpp"
#include "engine/scene/terminal_speed.hpp"

namespace ameoto {

namespace {
constexpr double min_distance_m = 0.5;
constexpr double water_density = 998.0;
}  // namespace

SceneSurfaces::SceneSurfaces(const SceneDescription& scene, double sample_rate, int channels, std::uint64_t seed,
                             double full_scale_pa, int node, bool ambisonic)
    : channels_(channels), ambisonic_(ambisonic), dt_(1.0 / sample_rate), inverse_full_scale_(1.0 / full_scale_pa) {
    if (ambisonic && ambix_order(channels) < 1) throw std::invalid_argument("an Ambisonic bus has 4, 9 or 16 channels");
    const ListenerDescription& l = scene.listener;
    listener_ = Vec3{l.x_m, l.y_m, l.z_m};
    facing_rad_ = l.facing_rad;
    const DropSizeDistribution dsd = drop_size_distribution_for(scene.rain);
    std::uint64_t k = 0;
    for (const SurfaceDescription& s : scene.surfaces) {
        if (s.kind == SurfaceKind::umbrella) continue;
        // k counts every surface of the scene, rendered here or not: a surface's streams do not depend on
        // which node renders it. The first surface's rain stream is the renderer's former shared one.
        const std::uint64_t stream = (seed ^ 0xD1B54A32D192ED03ull) + 0x9E3779B97F4A7C15ull * k;
        ++k;
        if (node != 0 && s.node != node) continue;
        auto source = make_surface_source(s, sample_rate, seed + 0x51ED27u * k);
        RainSpawner rain(RainSpawner::Config{.area_m2 = source->area_m2(), .dsd = dsd});
        rain.set_rate_now(scene.rain.rate_mm_per_h);
        PropagationConfig pc;
        pc.sample_rate = sample_rate;
        pc.max_distance_m = 2000.0;   // the scene file's positions reach 1000 m each way
        pc.min_distance_m = min_distance_m;
        placed_.push_back(Placed{std::move(source), std::move(rain), Random(stream), Propagation(pc), Vec3{s.x_m, s.y_m, s.z_m}, 1.0, {}});
        place(placed_.back(), true);
    }
}

void SceneSurfaces::place(Placed& p, bool now) {
    const Vec3 d = p.centre - listener_;
    p.distance_m = std::max(min_distance_m, norm(d));
    if (now) {
        p.path.set_positions_now(listener_, p.centre);
    } else {
        p.path.set_listener(listener_);
    }
    // Relative to the facing; the elevation only an Ambisonic bus hears (the panned formats are rings).
    const auto g = direction_gains(std::atan2(d.y, d.x) - facing_rad_, std::atan2(d.z, std::hypot(d.x, d.y)), channels_, ambisonic_);
    for (int c = 0; c < channels_; ++c) p.pan[static_cast<std::size_t>(c)] = static_cast<float>(g[static_cast<std::size_t>(c)]);
}

void SceneSurfaces::set_listener(double x_m, double y_m, double z_m, double facing_rad) {
    listener_ = Vec3{x_m, y_m, z_m};
    facing_rad_ = facing_rad;
    for (Placed& p : placed_) place(p, false);
}

void SceneSurfaces::set_rate(double mm_per_h) {
    for (Placed& p : placed_) p.rain.set_rate(mm_per_h);
}

void SceneSurfaces::set_rate_now(double mm_per_h) {
    for (Placed& p : placed_) p.rain.set_rate_now(mm_per_h);
}

void SceneSurfaces::render(float* frame, const Wind& wind) {
    // The scene's surfaces lie horizontal (scene_description.hpp).
    for (Placed& p : placed_) {
        Random& rng = p.rng;
        const int arrivals = p.rain.advance(dt_, rng);
        for (int a = 0; a < arrivals; ++a) {
            const double d = p.rain.sample_diameter_m(rng);
            const double u = rng.uniform(), v = rng.uniform();
            // The wind adds a horizontal speed the surface does not feel along its normal (the modules
            // take the normal speed); a horizontal surface's rate is the same in any wind (wind.hpp). Along
            // the vertical normal, Wind::impact's normal speed is the drop's fall speed, -(0 + 0 + v_z) =
            // v_t(D) exactly: taken directly, without the tangential part and its atan2 (heavy rain on a
            // pond is 85 000 drops per second).
            (void)wind;
            const double speed = std::max(0.5, terminal_speed(d));
            p.source->strike(d, speed, water_density, u, v, rng);
            ++drops_;
        }
        const double now = p.source->sample();
        const auto s = static_cast<float>(p.path.process(std::isfinite(now) ? now : 0.0) * inverse_full_scale_);
        for (int c = 0; c < channels_; ++c) frame[c] += p.pan[static_cast<std::size_t>(c)] * s;
    }
}

}  // namespace ameoto
