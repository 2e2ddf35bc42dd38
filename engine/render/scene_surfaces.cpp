#include "engine/render/scene_surfaces.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/physical_constants.hpp"
#include "engine/models/drop.hpp"

namespace ameoto {

SceneSurfaces::SceneSurfaces(const SceneDescription& scene, double sample_rate, int channels, std::uint64_t seed,
                             double full_scale_pa)
    : channels_(channels), dt_(1.0 / sample_rate) {
    const ListenerDescription& l = scene.listener;
    std::uint64_t k = 0;
    for (const SurfaceDescription& s : scene.surfaces) {
        if (s.kind == SurfaceKind::umbrella) continue;
        Placed p{make_surface_source(s, sample_rate, seed + 0x51ED27u * ++k), RainSpawner(RainSpawner::Config{}), 1.0, 0.0, 1.0, {}, {}, 0, 0, 0.0};
        p.rain = RainSpawner(RainSpawner::Config{.area_m2 = p.source->area_m2()});
        p.rain.set_rate_now(scene.rain.rate_mm_per_h);
        const double dx = s.x_m - l.x_m, dy = s.y_m - l.y_m, dz = s.z_m - l.z_m;
        p.distance_m = std::max(0.5, std::sqrt(dx * dx + dy * dy + dz * dz));
        p.gain = 1.0 / (p.distance_m * full_scale_pa);   // the source is referred to 1 m
        p.delay = p.distance_m / (constants::speed_of_sound_air * dt_);
        p.offset = static_cast<int>(std::floor(p.delay));
        p.frac = p.delay - p.offset;
        std::size_t length = 2;
        while (length < static_cast<std::size_t>(p.offset) + 2) length <<= 1;
        p.ring.assign(length, 0.0);
        const auto g = pan_gains(std::atan2(dy, dx) - l.facing_rad, channels);
        for (int c = 0; c < channels; ++c) p.pan[static_cast<std::size_t>(c)] = static_cast<float>(g[static_cast<std::size_t>(c)]);
        placed_.push_back(std::move(p));
    }
}

void SceneSurfaces::set_rate(double mm_per_h) {
    for (Placed& p : placed_) p.rain.set_rate(mm_per_h);
}

void SceneSurfaces::set_rate_now(double mm_per_h) {
    for (Placed& p : placed_) p.rain.set_rate_now(mm_per_h);
}

void SceneSurfaces::render(float* frame, Random& rng) {
    for (Placed& p : placed_) {
        const int arrivals = p.rain.advance(dt_, rng);
        for (int a = 0; a < arrivals; ++a) {
            const double d = p.rain.sample_diameter_m(rng);
            const double u = rng.uniform(), v = rng.uniform();
            p.source->strike(d, arrival_speed(d, density_), density_, u, v, rng);
            ++drops_;
        }
        const double now = p.source->sample();
        const std::size_t mask = p.ring.size() - 1;
        p.write = static_cast<int>((static_cast<std::size_t>(p.write) + 1) & mask);
        p.ring[static_cast<std::size_t>(p.write)] = std::isfinite(now) ? now : 0.0;
        // Linear interpolation between floor(D) and floor(D) + 1 samples ago (as radiation.hpp).
        const double a = p.ring[(static_cast<std::size_t>(p.write) - static_cast<std::size_t>(p.offset)) & mask];
        const double b = p.ring[(static_cast<std::size_t>(p.write) - static_cast<std::size_t>(p.offset) - 1) & mask];
        const auto s = static_cast<float>(p.gain * ((1.0 - p.frac) * a + p.frac * b));
        for (int c = 0; c < channels_; ++c) frame[c] += p.pan[static_cast<std::size_t>(c)] * s;
    }
}

}  // namespace ameoto
