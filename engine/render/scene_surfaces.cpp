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
        placed_.push_back(Placed{std::move(source), std::move(rain), Random(stream), Propagation(pc), Vec3{s.x_m, s.y_m, s.z_m}, 1.0, {}, {}, {}});
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
    std::array<double, max_ambix_channels> g{};
    if (ambisonic_) {
        // The world bus: the scene's frame; the renderer turns it (facing, head).
        g = direction_gains(std::atan2(d.y, d.x), std::atan2(d.z, std::hypot(d.x, d.y)), channels_, true);
    } else if (head_identity_) {
        g = direction_gains(std::atan2(d.y, d.x) - facing_rad_, 0.0, channels_, false);   // the rings: azimuth only
    } else {
        // The body's frame (turned by the facing about z), then the head's: H^T b; panned by its azimuth.
        const double cf = std::cos(facing_rad_), sf = std::sin(facing_rad_);
        const Vec3 b{cf * d.x + sf * d.y, -sf * d.x + cf * d.y, d.z};
        const std::array<double, 9>& h = head_;
        const double x = h[0] * b.x + h[3] * b.y + h[6] * b.z, y = h[1] * b.x + h[4] * b.y + h[7] * b.z;
        g = direction_gains(std::atan2(y, x), 0.0, channels_, false);
    }
    for (int c = 0; c < channels_; ++c) {
        const auto to = static_cast<float>(g[static_cast<std::size_t>(c)]);
        p.pan_to[static_cast<std::size_t>(c)] = to;
        if (now) p.pan[static_cast<std::size_t>(c)] = to;
    }
}

// Every surface's gains glide from where they are (mid-glide too) to their new targets.
void SceneSurfaces::glide_all() {
    for (Placed& p : placed_)
        for (int c = 0; c < channels_; ++c) {
            const auto k = static_cast<std::size_t>(c);
            p.pan_step[k] = (p.pan_to[k] - p.pan[k]) / static_cast<float>(pan_glide_frames);
        }
    glide_left_ = pan_glide_frames;
}

void SceneSurfaces::set_listener(double x_m, double y_m, double z_m, double facing_rad) {
    listener_ = Vec3{x_m, y_m, z_m};
    facing_rad_ = facing_rad;
    for (Placed& p : placed_) place(p, false);
    glide_all();
}

void SceneSurfaces::set_head(const std::array<double, 9>& head) {
    if (ambisonic_) return;   // the renderer rotates the bus
    head_ = head;
    head_identity_ = head == std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (Placed& p : placed_) place(p, false);
    glide_all();
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
    if (glide_left_ > 0) {   // the gains step towards their targets; exactly there at the end
        const bool last = --glide_left_ == 0;
        for (Placed& p : placed_)
            for (int c = 0; c < channels_; ++c) {
                const auto k = static_cast<std::size_t>(c);
                p.pan[k] = last ? p.pan_to[k] : p.pan[k] + p.pan_step[k];
            }
    }
}

}  // namespace ameoto
