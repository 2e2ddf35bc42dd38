// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/membrane_collision.hpp"

#include <cmath>
#include <stdexcept>

namespace ameoto {

MembraneCollider::MembraneCollider(const Canopy& canopy, double time_step_s, const CollisionOptions& options)
    : options_(options), law_(options.law()), time_step_(time_step_s), nodes_per_panel_(canopy.nodes_per_panel()) {
    if (!(time_step_s > 0.0) || !std::isfinite(time_step_s)) throw std::invalid_argument("time step must be positive");
    if (!(options.restitution >= 0.0 && options.restitution <= 1.0))
        throw std::invalid_argument("restitution must be 0 to 1 (1: elastic; above 1 a collision would create energy)");
    if (!(options.skin_m >= 0.0) || !std::isfinite(options.skin_m)) throw std::invalid_argument("skin must be >= 0 m");
    if (!(options.liquid_density > 0.0) || !std::isfinite(options.liquid_density))
        throw std::invalid_argument("liquid density must be positive");
    if (!(options.max_reach_m >= 0.0 && options.max_reach_m <= 0.01))
        throw std::invalid_argument("reach cap must be 0 to 10 mm");
    const std::size_t n = static_cast<std::size_t>(canopy.panel_count()) * static_cast<std::size_t>(nodes_per_panel_);
    pending_.assign(n, 0.0);
    stamp_.assign(n, 0);
}

void MembraneCollider::begin_step() { ++step_; }

bool MembraneCollider::collide_one(Canopy& canopy, Vec3 p, Vec3 v, double m1, Vec3& drop_force,
                                   MembraneCollision* record) {
    const CanopyHit hit = canopy.locate(p.x, p.y);
    if (hit.panel < 0) return false;
    // Height above the membrane: the rest cap's normal distance under (x, y), less the node's u.
    const double h =
        (p.z - canopy.rest_height(p.x, p.y)) * canopy.surface_normal(p.x, p.y).z - canopy.displacement(hit.panel, hit.node);
    if (m1 != memo_mass_) {   // the cube root once per mass size (a drop's masses are all one size)
        memo_mass_ = m1;
        memo_parcel_ = law_.parcel(m1);
        memo_reach_ = law_.reach(m1);
    }
    if (!(h <= memo_reach_)) return false;
    const auto slot = static_cast<std::size_t>(hit.panel * nodes_per_panel_ + hit.node);
    if (stamp_[slot] != step_) {
        stamp_[slot] = step_;
        pending_[slot] = 0.0;
    }
    const Vec3 n = canopy.normal(hit.panel, hit.node);
    const double v1 = dot(v, n);
    const double v2 = canopy.normal_velocity(hit.panel, hit.node) + pending_[slot];
    const double m2 = canopy.contact_mass(hit.panel, hit.node);   // in air: with the air it carries (air_canopy.hpp)
    const ContactImpulse c = contact_impulse_of_parcel(law_, memo_parcel_, m1, m2, h, v1, v2, time_step_);   // wet_impact.hpp
    if (!c.contact) return false;
    const double impulse = c.impulse;   // on the drop mass, along n
    const double v1_after = v1 + impulse / m1, v2_after = v2 - impulse / m2;
    drop_force = (impulse / time_step_) * n;
    canopy.apply_force(hit, -impulse / time_step_);
    pending_[slot] += v2_after - v2;
    ++collisions_;
    if (record != nullptr) {
        record->panel = hit.panel;
        record->node = hit.node;
        record->normal = n;
        record->m1 = m1;
        record->m2 = m2;
        record->v1 = v1;
        record->v2 = v2;
        record->v1_after = v1_after;
        record->v2_after = v2_after;
        record->impulse = impulse;
        record->depth = -h;
    }
    return true;
}

}  // namespace ameoto
