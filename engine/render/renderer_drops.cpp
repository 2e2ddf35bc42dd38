// SPDX-License-Identifier: GPL-3.0-or-later
// Where each drop goes, on the audio thread: a /drop (the lattice pool, or a template when the pool is
// full) and each rain drop (the level-of-detail governor's tier: full, template or texture grain). The
// rest of the Renderer (construction, commands, the sample loop) is renderer.cpp.
#include "engine/render/renderer.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/physical_constants.hpp"
#include "engine/models/drop.hpp"

namespace ameoto {

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

}  // namespace ameoto
