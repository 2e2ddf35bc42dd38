#include "engine/models/drop_on_canopy.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/models/drop.hpp"

namespace ameoto {
namespace {

DropPoolConfig pool_config(const DropOnCanopyConfig& c) {
    DropPoolConfig p;
    p.capacity = c.capacity;
    p.max_diameter = c.max_diameter;
    p.time_step = 1.0 / c.sample_rate;
    p.max_sub_steps = 64;   // low sample rates need more sub-steps for the drops' cores
    p.retire_below = c.retire_below_m;
    p.max_lifetime = c.max_lifetime_s;
    return p;
}

ListenerLayout layout_for(const DropOnCanopyConfig& c) {
    const Vec3 head{0.0, 0.0, -c.listener_below_m};
    return c.channels == 2 ? ListenerLayout::ears(head, 0.0) : ListenerLayout::mono(head);
}

std::string number(double v) {
    std::string s = std::to_string(v);
    return s;
}

}  // namespace

const DropOnCanopyConfig& DropOnCanopy::checked(const DropOnCanopyConfig& c) {
    if (!(c.sample_rate >= 8000.0 && c.sample_rate <= 384000.0))
        throw std::invalid_argument("sample rate " + number(c.sample_rate) + " Hz is outside 8000..384000");
    if (c.channels != 1 && c.channels != 2)
        throw std::invalid_argument("channels must be 1 or 2, not " + std::to_string(c.channels));
    if (!(c.restitution >= 0.0 && c.restitution <= 1.0))
        throw std::invalid_argument("restitution " + number(c.restitution) + " is outside 0..1");
    if (c.capacity < 1 || c.capacity > 256)
        throw std::invalid_argument("capacity " + std::to_string(c.capacity) + " is outside 1..256");
    if (!(c.gap_m >= 0.0 && c.gap_m <= 0.1)) throw std::invalid_argument("gap " + number(c.gap_m) + " m is outside 0..0.1");
    if (!(c.full_scale_pa > 0.0 && std::isfinite(c.full_scale_pa)))
        throw std::invalid_argument("full scale must be a positive pressure (Pa)");
    if (!(c.listener_below_m > 0.0 && c.listener_below_m < 100.0))
        throw std::invalid_argument("listener distance " + number(c.listener_below_m) + " m is outside 0..100");
    if (const std::string why = validate(c.liquid); !why.empty()) throw std::invalid_argument(why);
    if (const MaterialCheck m = validate_membrane_material(c.material); !m.ok) throw std::invalid_argument(m.reason);
    return c;
}

DropOnCanopy::DropOnCanopy(const DropOnCanopyConfig& config)
    : config_(checked(config)),
      dt_(1.0 / config_.sample_rate),
      canopy_(config_.geometry, config_.material, dt_),
      pool_(pool_config(config_)),
      collider_(canopy_, dt_, CollisionOptions{.restitution = config_.restitution}),
      far_field_(canopy_, layout_for(config_), dt_),
      pickup_(MassPickup::at(canopy_, config_.pickup_x, config_.pickup_y)),
      panel_forces_(static_cast<std::size_t>(canopy_.panel_count()), 0.0),
      pressures_(static_cast<std::size_t>(far_field_.channels()), 0.0),
      spawn_masses_(static_cast<std::size_t>(config_.capacity), 0),
      spawn_mass_kg_(static_cast<std::size_t>(config_.capacity), 0.0) {
    liquid_ = pool_.add_liquid(config_.liquid);
    // The rest cap's top (at the shaft) and rim; collide() sets reach_ every step from the membrane's
    // displacement (no mass higher than top_ + reach_ can touch it). bottom_ is not used any more.
    top_ = canopy_.rest_height(0.0, 0.0);
    bottom_ = canopy_.rest_height(canopy_.geometry().radius_m, 0.0);
    reach_ = 0.0;
}

bool DropOnCanopy::drop(double diameter_m, double speed_m_per_s, double x_m, double y_m) {
    if (!(diameter_m > 0.0 && diameter_m <= config_.max_diameter)) return false;
    if (!(speed_m_per_s >= 0.0 && std::isfinite(speed_m_per_s))) return false;
    if (canopy_.locate(x_m, y_m).panel < 0) return false;
    const double speed = speed_m_per_s > 0.0 ? speed_m_per_s : arrival_speed(diameter_m, config_.liquid.density);
    const double z = canopy_.rest_height(x_m, y_m) + 0.5 * diameter_m + config_.gap_m;
    if (!pool_.spawn(diameter_m, liquid_, Vec3{x_m, y_m, z}, Vec3{0.0, 0.0, -speed})) return false;
    // The new drop has the highest serial.
    int slot = -1;
    std::uint64_t best = 0;
    for (const int d : pool_.active())
        if (pool_.serial(d) >= best) {
            best = pool_.serial(d);
            slot = d;
        }
    if (slot >= 0 && static_cast<std::size_t>(slot) < spawn_masses_.size()) {
        const int n = pool_.mass_count(slot);
        double kg = 0.0;
        for (int m = 0; m < n; ++m) kg += pool_.mass(slot, m);
        spawn_masses_[static_cast<std::size_t>(slot)] = n;
        spawn_mass_kg_[static_cast<std::size_t>(slot)] = kg;
    }
    return true;
}

void DropOnCanopy::process(int frames, float* const* outputs) {
    const int channels = config_.channels;
    const double inverse_full_scale = 1.0 / config_.full_scale_pa;
    for (int i = 0; i < frames; ++i) {
        collide();
        canopy_.step(panel_forces_.data());
        pool_.step();
        if (config_.output == SceneOutput::far_field) {
            far_field_.process(canopy_, pressures_.data());
            for (int c = 0; c < channels; ++c)
                outputs[c][i] = static_cast<float>(pressures_[static_cast<std::size_t>(c)] * inverse_full_scale);
        } else {
            const auto s = static_cast<float>(pickup_.sample(canopy_));
            for (int c = 0; c < channels; ++c) outputs[c][i] = std::isfinite(s) ? s : 0.0f;
        }
        if ((++frames_ & 255u) == 0) canopy_resets_ += canopy_.reset_unstable();
    }
}

// MembraneCollider::collide_drops, mass by mass, skipping the masses that collide_one would turn away
// anyway (collision detection, Canopy::locate, is most of a sample's cost once a drop has landed or
// shattered: most of its masses are above the layer that touches the membrane, or flying off). The
// masses that remain are collided exactly as collide_drops would, in the same order, so the result is
// identical to the bit (tested against collide_drops itself). collide_one (membrane_collision.cpp)
// collides a mass at p, velocity v, over node j of a panel, only if
//   h = a - u_j <= 0, with a = (p_z - z_rest(x, y)) n_z(x, y) (its height over the rest cap), and
//   closing = v . n_j - (du_j/dt + pending_j) < 0, and -h < T (-closing) + skin.
// So a mass is skipped when
//   - it is off the rim's circle: every panel (a triangle from the shaft to two rib tips at radius R)
//     lies inside it (with a relative 1e-12 for the rounding of the rib tips' coordinates);
//   - a > max_j u_j: then h > 0 for every node. a is computed by the same calls and operations as in
//     collide_one (on a flat canopy z_rest = +0 and n_z = 1, so a is p_z itself), and a correctly
//     rounded a - u_j is <= 0 exactly when a <= u_j, so the test is exact (were collide_one's product
//     fused with its subtraction, its h <= 0 would mean the exact product <= u_j, which implies
//     a <= u_j for the rounded product too). A quicker form first, without the cap's square roots:
//     p_z > top_ + reach_, reach_ = max(max u, 0) / n_z(rim) (with 1e-9 of it and 1e-12 m for the
//     rounding and the rim's 1e-12): inside the rim z_rest <= top_ and n_z >= n_z(rim), so then
//     a >= (p_z - top_) n_z(rim) > max u;
//   - a <= min_j u_j - skin - T (max_j du_j/dt + |v|_1) - slack: pending_j (the velocity this step's
//     earlier collisions gave node j) is never positive (each collision's impulse pushes the node down,
//     away from the drop: J >= 0), so v2 <= max du/dt, and v . n_j >= -|v| >= -|v|_1 (n_j is a unit
//     vector), so -closing <= max du/dt + |v|_1 and -h = u_j - a >= min u - a: the swept test fails.
//     `slack` covers the rounding of both sides (a few ulps of the terms; 1e-9 of them is ample).
// The canopy does not move during collide() (it steps afterwards), so the node bounds hold for the
// whole step; they are read once, and only if some mass needs them (max u at the first mass inside the
// rim; min u and max du/dt at the first mass deeper than the skin below the rest cap, rare: a drop
// comes from above). A node gone NaN is passed over by the bounds and never collides in collide_one.
// Reading max u is a pass over every node (a call per node: 400 for the default canopy), about as
// costly as looking up 20 masses; so with fewer than 24 masses in the pool, every mass inside the rim
// is simply looked up (as exact, cheaper for small drops).
void DropOnCanopy::collide() {
    collider_.begin_step();
    const double r = canopy_.geometry().radius_m;
    const double r2_max = r * r * (1.0 + 1e-12);
    const bool flat = canopy_.flat();
    const double skin = collider_.options().skin_m, t = collider_.time_step();
    int masses = 0;
    for (const int d : pool_.active()) masses += pool_.mass_count(d);
    const bool bounded = masses >= 24;
    bool have_top = false, have_bottom = false;
    double u_max = 0.0, u_min = 0.0, w_max = 0.0;
    for (const int d : pool_.active()) {
        const int n = pool_.mass_count(d);
        for (int m = 0; m < n; ++m) {
            const Vec3 p = pool_.position(d, m);
            if (p.x * p.x + p.y * p.y > r2_max) continue;
            double a = 0.0;
            if (bounded) {
                if (!have_top) {
                    u_max = canopy_.max_displacement();
                    reach_ = std::max(u_max, 0.0) * (1.0 + 1e-9) / canopy_.surface_normal(r, 0.0).z + 1e-12;
                    have_top = true;
                }
                if (p.z > top_ + reach_) continue;
                a = flat ? p.z : (p.z - canopy_.rest_height(p.x, p.y)) * canopy_.surface_normal(p.x, p.y).z;
                if (a > u_max) continue;
            }
            const Vec3 v = pool_.velocity(d, m);
            if (bounded && a < -skin) {
                if (!have_bottom) {
                    u_min = canopy_.min_displacement();
                    w_max = canopy_.max_normal_velocity();
                    have_bottom = true;
                }
                const double reach = skin + t * (w_max + std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z));
                const double depth = u_min - a;
                const double slack = 1e-9 * (std::fabs(u_min) + std::fabs(a) + std::fabs(reach) + t * std::fabs(w_max));
                if (depth >= reach + slack) continue;
            }
            Vec3 force;
            if (collider_.collide_one(canopy_, p, v, pool_.mass(d, m), force)) pool_.apply_force(d, m, force);
        }
    }
}

DropOnCanopyStats DropOnCanopy::stats() const {
    DropOnCanopyStats s;
    for (const int d : pool_.active()) {
        ++s.active_drops;
        const int pieces = pool_.pieces(d);
        s.pieces += pieces;
        s.largest_pieces = std::max(s.largest_pieces, pieces);
        const int n = pool_.mass_count(d);
        s.masses += n;
        double kg = 0.0;
        for (int m = 0; m < n; ++m) kg += pool_.mass(d, m);
        s.mass_kg += kg;
        s.masses_at_spawn += spawn_masses_[static_cast<std::size_t>(d)];
        s.mass_at_spawn_kg += spawn_mass_kg_[static_cast<std::size_t>(d)];
    }
    const DropPoolStats& p = pool_.stats();
    s.spawned = p.spawned;
    s.retired = p.retired;
    s.breakups = p.breakups;
    s.link_breaks = p.link_breaks;
    s.collisions = collider_.collisions();
    s.canopy_resets = canopy_resets_;
    s.frames = frames_;
    return s;
}

std::vector<SceneMass> DropOnCanopy::snapshot() const {
    std::vector<SceneMass> out;
    for (const int d : pool_.active()) {
        const int n = pool_.mass_count(d);
        const bool whole = pool_.dormant(d);   // a dormant drop is one piece; piece_of is not computed yet
        for (int m = 0; m < n; ++m)
            out.push_back(SceneMass{pool_.position(d, m), pool_.velocity(d, m), d, pool_.serial(d),
                                    whole ? 0 : pool_.piece_of(d, m)});
    }
    return out;
}

}  // namespace ameoto
