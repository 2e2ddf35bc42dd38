// SPDX-License-Identifier: GPL-3.0-or-later
// The umbrella scene with lattice drops: its configuration checks, construction, a drop's spawn, the
// sample step and its outputs, the guard, stats and snapshots. The collisions with the membrane and the
// coarse-step floors (collide, set_drop_floors) are drop_on_canopy_collide.cpp.
#include "engine/models/drop_on_canopy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "engine/core/physical_constants.hpp"
#include "engine/models/ambisonics.hpp"
#include "engine/models/collision_scan.hpp"
#include "engine/models/drop.hpp"
#include "engine/models/panning.hpp"

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
    p.coarse_max = c.coarse_steps;
    p.park_done = c.settle;
    // Wet: the lattice tilted (drop.hpp, drop_orientation), so that its masses reach the membrane one by
    // one, not a plane at a time; the seed's lattice stands upright.
    p.options.tilted = c.impact == ImpactModel::wet;
    return p;
}

ListenerLayout layout_for(const DropOnCanopyConfig& c) {
    const Vec3 head{0.0, 0.0, -c.listener_below_m};
    if (c.channels == 1) return ListenerLayout::mono(head);
    if (c.channels == 2 && c.listener == ListenerStyle::ears) return ListenerLayout::ears(head, 0.0);
    // Panned: one listening point; each panel's pressure spread over the speakers by its azimuth.
    const Canopy shape(c.geometry, c.material, 1.0 / c.sample_rate);
    std::vector<std::vector<double>> gains(static_cast<std::size_t>(c.channels),
                                           std::vector<double>(static_cast<std::size_t>(shape.panel_count())));
    for (int k = 0; k < shape.panel_count(); ++k) {
        // Ambisonics: the panel encoded by the direction of its centre (the mean of its nodes' rest
        // points) from the head, elevation included; a panel's nodes are all within its sector.
        Vec3 centre{};
        for (int i = 0; i < shape.nodes_per_panel(); ++i) centre = centre + shape.rest_position(k, i);
        const Vec3 d = centre / shape.nodes_per_panel() - head;
        const auto g = c.listener == ListenerStyle::ambix
                           ? ambix_gains(d, ambix_order(c.channels))
                           : direction_gains(shape.panel_azimuth(k), 0.0, c.channels, false);
        for (int ch = 0; ch < c.channels; ++ch)
            gains[static_cast<std::size_t>(ch)][static_cast<std::size_t>(k)] = g[static_cast<std::size_t>(ch)];
    }
    return ListenerLayout::panned(head, std::move(gains));
}

std::string number(double v) {
    std::string s = std::to_string(v);
    return s;
}

}  // namespace

std::function<bool(Vec3, Vec3)> settle_predicate(const DropOnCanopyConfig& c, double touch_m) {
    const double r = c.geometry.radius_m, rc = c.geometry.curvature_radius_m, below = c.retire_below_m;
    const double rest_speed = c.rest_speed_m_per_s;
    const bool flat = !std::isfinite(rc);
    // The rest cap, as Canopy::rest_height and surface_normal compute it (canopy.hpp).
    auto rest_z = [=](double r2) { return flat ? 0.0 : -r2 / (std::sqrt(rc * rc - r2) + rc); };
    const double out2 = (r + 0.01) * (r + 0.01);
    return [=](Vec3 p, Vec3 v) {
        if (p.z < below) return true;
        const double r2 = p.x * p.x + p.y * p.y;
        if (r2 > out2 && p.x * v.x + p.y * v.y >= 0.0) return true;   // gone past the rim, outwards
        if (r2 > r * r) return false;
        const Vec3 n = flat ? Vec3{0.0, 0.0, 1.0} : Vec3{p.x / rc, p.y / rc, std::sqrt(1.0 - r2 / (rc * rc))};
        const double h = (p.z - rest_z(r2)) * n.z;   // over the rest cap, along its normal
        if (h < -0.05 && v.z <= 0.0) return true;     // under the band the membrane never reaches
        return h <= touch_m + 1e-3 && h >= -3e-3 && std::fabs(dot(v, n)) < rest_speed;   // at rest on it
    };
}

CollisionOptions collision_options(const DropOnCanopyConfig& c) {
    return c.impact == ImpactModel::seed ? CollisionOptions::seed(c.restitution) : CollisionOptions::wet(c.liquid.density);
}

const DropOnCanopyConfig& DropOnCanopy::checked(const DropOnCanopyConfig& c) {
    if (!(c.sample_rate >= 8000.0 && c.sample_rate <= 384000.0))
        throw std::invalid_argument("sample rate " + number(c.sample_rate) + " Hz is outside 8000..384000");
    if (c.channels < 1 || c.channels > max_pan_channels)
        throw std::invalid_argument("channels must be 1 to 16, not " + std::to_string(c.channels));
    if (c.listener == ListenerStyle::ambix && ambix_order(c.channels) < 1)
        throw std::invalid_argument("an Ambisonic listener needs 4, 9 or 16 channels, not " + std::to_string(c.channels));
    if (!(c.restitution >= 0.0 && c.restitution <= 1.0))
        throw std::invalid_argument("restitution " + number(c.restitution) + " is outside 0..1");
    if (c.impact != ImpactModel::wet && c.impact != ImpactModel::seed) throw std::invalid_argument("unknown impact model");
    if (!(c.rest_speed_m_per_s >= 0.0 && c.rest_speed_m_per_s <= 10.0))
        throw std::invalid_argument("rest speed " + number(c.rest_speed_m_per_s) + " m/s is outside 0..10");
    if (c.guard_interval < 0) throw std::invalid_argument("guard interval must be 0 or more samples");
    if (c.coarse_steps < 1 || c.coarse_steps > 64)
        throw std::invalid_argument("coarse steps " + std::to_string(c.coarse_steps) + " is outside 1..64");
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

Canopy DropOnCanopy::fresh_canopy(const DropOnCanopyConfig& config) {
    const DropOnCanopyConfig& c = checked(config);
    Canopy canopy(c.geometry, c.material, 1.0 / c.sample_rate, c.network);
    if (c.air) canopy.set_air(build_air_canopy_modes(canopy, 1.0 / c.sample_rate, c.air_options));
    return canopy;
}

DropOnCanopy::DropOnCanopy(const DropOnCanopyConfig& config) : DropOnCanopy(Built{}, config, fresh_canopy(config)) {}

namespace {

// A prototype of another geometry would give another scene; the material, time step and integrator
// cannot be read back from a Canopy, so those stay the caller's promise (the header).
const Canopy& matching(const Canopy& prototype, const DropOnCanopyConfig& c) {
    const CanopyGeometry& g = prototype.geometry();
    if (g.panels != c.geometry.panels || g.radius_m != c.geometry.radius_m ||
        g.masses_per_panel != c.geometry.masses_per_panel || g.curvature_radius_m != c.geometry.curvature_radius_m)
        throw std::invalid_argument("the prototype canopy's geometry is not the configuration's");
    return prototype;
}

}  // namespace

// The configuration is checked before the geometry: the same errors as the one-argument constructor.
DropOnCanopy::DropOnCanopy(const DropOnCanopyConfig& config, const Canopy& prototype)
    : DropOnCanopy(Built{}, config, Canopy(matching(prototype, checked(config)))) {}

DropOnCanopy::DropOnCanopy(const DropOnCanopyConfig& config, const Canopy& prototype, const DropOnCanopy& sibling)
    : DropOnCanopy(Built{}, config, Canopy(matching(prototype, checked(config))), &sibling) {}

DropOnCanopy::DropOnCanopy(Built, const DropOnCanopyConfig& config, Canopy&& canopy, const DropOnCanopy* sibling)
    : config_(config),
      dt_(1.0 / config_.sample_rate),
      canopy_(std::move(canopy)),
      pool_(pool_config(config_)),
      collider_(canopy_, dt_, collision_options(config_)),
      far_field_(canopy_, layout_for(config_), dt_),
      pickup_(MassPickup::at(canopy_, config_.pickup_x, config_.pickup_y)),
      panel_forces_(static_cast<std::size_t>(canopy_.panel_count()), 0.0),
      pressures_(static_cast<std::size_t>(far_field_.channels()), 0.0),
      spawn_masses_(static_cast<std::size_t>(config_.capacity), 0),
      spawn_mass_kg_(static_cast<std::size_t>(config_.capacity), 0.0) {
    liquid_ = pool_.add_liquid(config_.liquid);
    // A prototype in air (fresh_canopy) brings its modes; otherwise they are built here.
    if (config_.air && !canopy_.in_air()) canopy_.set_air(build_air_canopy_modes(canopy_, dt_, config_.air_options));
    if (!config_.air && canopy_.in_air()) canopy_.set_air(nullptr);
    // The dipoles are heard only in the far field: a mass pickup (the impact templates' 51 runs) has none
    // to build (their build was a quarter of a scene's in air).
    if (config_.air && config_.output == SceneOutput::far_field)
        dipole_ = DipoleRadiation(canopy_, far_field_.layout(), dt_, AirMedium{config_.air_options.air_density, config_.air_options.speed_of_sound},
                                  DipoleOptions{.compressible_push = config_.air_push}, sibling ? &sibling->dipole_ : nullptr);
    // The band collide() keeps to (see there): the rest cap spans bottom_ (its rim) to top_ (the shaft);
    // the normal's vertical component is smallest at the rim, so reach_ vertically is at least 5 cm
    // along any normal inside the rim's circle.
    const double r = canopy_.geometry().radius_m;
    top_ = canopy_.rest_height(0.0, 0.0);
    bottom_ = canopy_.rest_height(r, 0.0);
    rim_normal_z_ = canopy_.surface_normal(r, 0.0).z;
    reach_ = 0.05 / rim_normal_z_;
    touch_ = config_.impact == ImpactModel::seed ? 0.0 : collider_.options().max_reach_m;
    pool_.set_coarse_floor(top_ + reach_);   // collide() sets it each sample (see there)
    if (config_.settle) pool_.set_retire_predicate(settle_predicate(config_, touch_));
    double shortest = 1e300;
    const RayleighRadiator& radiator = far_field_.radiator();
    for (int p = 0; p < radiator.point_count(); ++p)
        for (int e = 0; e < radiator.element_count(); ++e) shortest = std::min(shortest, radiator.delay_samples(p, e));
    listener_points_ = far_field_.layout().points;
    latency_samples_ = config_.output == SceneOutput::far_field ? static_cast<int>(std::floor(shortest)) : 0;
    scan_.assign(static_cast<std::size_t>(pool_.max_masses()), 0);
    node_velocities_.assign(static_cast<std::size_t>(canopy_.lanes() * canopy_.nodes_per_panel()), 0.0);
    prepare_turn();
}

bool DropOnCanopy::drop(double diameter_m, double speed_m_per_s, double x_m, double y_m) {
    if (!(diameter_m > 0.0 && diameter_m <= config_.max_diameter)) return false;
    if (!(speed_m_per_s >= 0.0 && std::isfinite(speed_m_per_s))) return false;
    if (canopy_.locate(x_m, y_m).panel < 0) return false;
    const double speed = speed_m_per_s > 0.0 ? speed_m_per_s : arrival_speed(diameter_m, config_.liquid.density);
    // Wet: the lowest mass's parcel, not its centre, gap_m over the surface (it touches at its reach;
    // 1 nm inside it, so that with gap_m = 0 the rounding of the sums below cannot leave it a hair out
    // and the strike still comes at the first sample).
    const double reach = collider_.reach(calibrate_drop(pool_.lattice(seed_mass_count(diameter_m)), diameter_m,
                                                        config_.liquid, pool_.config().options).node_mass);
    const double touch = reach > 0.0 ? reach - 1e-9 : 0.0;
    const double z = canopy_.rest_height(x_m, y_m) + pool_.underside(diameter_m) + touch + config_.gap_m;
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
    float frame[max_pan_channels];
    for (int i = 0; i < frames; ++i) {
        process_frame(frame);
        for (int c = 0; c < config_.channels; ++c) outputs[c][i] = frame[c];
    }
}

void DropOnCanopy::process_frame(float* frame) {
    const int channels = config_.channels;
    collide();
    canopy_.step(panel_forces_.data());
    pool_.step();
    if (config_.output == SceneOutput::far_field) {
        if (config_.air)
            dipole_.process(canopy_, pressures_.data());
        else
            far_field_.process(canopy_, pressures_.data());
        const double inverse_full_scale = 1.0 / config_.full_scale_pa;
        for (int c = 0; c < channels; ++c) {
            // A panel that went non-finite is muted here and reset by the guard below.
            const double p = pressures_[static_cast<std::size_t>(c)] * inverse_full_scale;
            frame[c] = std::isfinite(p) ? static_cast<float>(p) : 0.0f;
        }
    } else {
        const auto s = static_cast<float>(pickup_.sample(canopy_));
        for (int c = 0; c < channels; ++c) frame[c] = std::isfinite(s) ? s : 0.0f;
    }
    ++frames_;
    if (config_.guard_interval > 0 && frames_ % static_cast<std::uint64_t>(config_.guard_interval) == 0) guard();
}

int DropOnCanopy::guard() {
    const int resets = canopy_.reset_unstable();
    canopy_resets_ += resets;
    return resets;
}

double DropOnCanopy::acoustic_delay_samples(double x_m, double y_m) const {
    if (config_.output != SceneOutput::far_field) return 0.0;
    const Vec3 at{x_m, y_m, canopy_.rest_height(x_m, y_m)};
    double shortest = 1e300;
    for (const Vec3& p : listener_points_) shortest = std::min(shortest, norm(p - at));
    return shortest / (constants::speed_of_sound_air * dt_);
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
    s.drops_passed_over = drops_passed_over_;
    s.drops_passed_over_in_band = drops_passed_over_in_band_;
    s.canopy_resets = canopy_resets_;
    s.frames = frames_;
    return s;
}

std::vector<SceneMass> DropOnCanopy::snapshot() const {
    std::vector<SceneMass> out;
    for (const int d : pool_.active()) {
        const int n = pool_.mass_count(d);
        const bool whole = pool_.dormant(d);   // a dormant drop is one piece; piece_of is not computed yet
        for (int m = 0; m < n; ++m) {
            const bool parked = pool_.parked(d, m);
            const Vec3 lift{0.0, 0.0, parked ? pool_.config().park_lift : 0.0};
            out.push_back(SceneMass{pool_.position(d, m) - lift, pool_.velocity(d, m), d, pool_.serial(d),
                                    whole ? 0 : pool_.piece_of(d, m), parked});
        }
    }
    return out;
}

}  // namespace ameoto
