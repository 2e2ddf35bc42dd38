// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/drop_pool.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "engine/core/body3d_drag.hpp"

namespace ameoto {

DropPool::DropPool(const DropPoolConfig& config) : config_(config) {
    if (config_.capacity < 1) throw std::invalid_argument("drop pool: capacity must be >= 1");
    if (!(config_.max_diameter > 0.0) || config_.max_diameter > 20e-3)
        throw std::invalid_argument("drop pool: max diameter must be in (0, 20 mm]");
    if (!(config_.time_step > 0.0) || !std::isfinite(config_.time_step)) throw std::invalid_argument("drop pool: time step must be positive");
    if (config_.max_liquids < 1 || config_.retire_interval < 1 || config_.max_sub_steps < 1)
        throw std::invalid_argument("drop pool: max liquids, max sub-steps and retire interval must be >= 1");
    if (config_.coarse_max < 1 || config_.coarse_max > 64) throw std::invalid_argument("drop pool: coarse max must be in 1..64");

    // Every mass count a diameter up to the largest can ask for (drop_lattice caches across pools).
    max_target_ = seed_mass_count(config_.max_diameter);
    const auto table = drop_lattices(max_target_);
    lattices_.resize(static_cast<std::size_t>(max_target_) + 1);
    int max_links = 0;
    for (int t = 1; t <= max_target_; ++t) {
        lattices_[static_cast<std::size_t>(t)] = table[static_cast<std::size_t>(t - 1)];
        max_masses_ = std::max(max_masses_, lattices_[static_cast<std::size_t>(t)]->mass_count());
        max_links = std::max(max_links, lattices_[static_cast<std::size_t>(t)]->shape.link_count());
    }
    lattices_[0] = lattices_[1];

    liquids_.reserve(static_cast<std::size_t>(config_.max_liquids));
    slots_.resize(static_cast<std::size_t>(config_.capacity));
    for (auto& s : slots_) {
        s.body.reserve(max_masses_, max_links);
        s.body.set_gravity(config_.gravity);
        s.body.set_integrator(config_.integrator);
        s.components.init(max_masses_, max_links);
        s.piece_live.assign(static_cast<std::size_t>(std::max(max_masses_, 1)), 0);
    }
    active_.reserve(slots_.size());
    free_.reserve(slots_.size());
    for (int i = config_.capacity - 1; i >= 0; --i) free_.push_back(i);   // slot 0 is taken first
    const double floor = config_.retire_below;
    done_ = [floor](Vec3 p, Vec3) { return p.z < floor; };
}

namespace {

// What add_liquid's check finds depends only on these (the lattices follow from max_diameter; a
// scratch body has the default speed bound, and gravity does not enter the bound): the check is run
// once per process for each, not once per pool. The scene's build makes a pool for each of its ~50
// impact templates and its texture calibration, all with the same liquid and step: each used to build
// and finalize ~120 drop bodies here (about 15 % of ameotod's start-up).
struct SubStepKey {
    double max_diameter, time_step, density, surface_tension, viscosity;
    Integrator integrator;
    bool core;
    double core_length, core_speed;
    auto tie() const {
        return std::tie(max_diameter, time_step, density, surface_tension, viscosity, integrator, core, core_length, core_speed);
    }
    bool operator<(const SubStepKey& o) const { return tie() < o.tie(); }
};

// Per checked drop, in the check's order: its diameter and the sub-steps it needs (4097: refused by finalize).
using SubStepNeeds = std::vector<std::pair<double, int>>;

// Bounded: a performer sweeping a custom liquid's values live (/material/liquid) makes a new key per
// value, and a server runs for hours. Past `limit` keys the cache starts again (callers hold their
// entries by shared_ptr); a scene's build needs one or two keys, so this costs nothing in practice.
struct SubStepCache {
    static constexpr std::size_t limit = 32;
    std::mutex mutex;
    std::map<SubStepKey, std::shared_ptr<const SubStepNeeds>> needs;
};

SubStepCache& sub_step_cache() {
    static SubStepCache instance;
    return instance;
}

}  // namespace

std::size_t DropPool::cached_liquid_checks() {
    SubStepCache& cache = sub_step_cache();
    std::lock_guard lock(cache.mutex);
    return cache.needs.size();
}

std::shared_ptr<const std::vector<std::pair<double, int>>> DropPool::sub_step_needs(const Liquid& liquid) const {
    const SubStepKey key{config_.max_diameter, config_.time_step, liquid.density, liquid.surface_tension, liquid.viscosity,
                         config_.integrator, config_.options.core, config_.options.core_length, config_.options.core_speed};
    SubStepCache& cache = sub_step_cache();
    {
        std::lock_guard lock(cache.mutex);
        if (auto it = cache.needs.find(key); it != cache.needs.end()) return it->second;
    }
    // Every lattice at the two ends of its diameter range: the dampers grow with viscosity
    // (z ~ mu a k / sigma), the core with 1 / h^2. Computed outside the lock; if another thread stored
    // the same meanwhile, the first stored wins (the values are the same).
    auto needs = std::make_shared<SubStepNeeds>();
    Body3D scratch;
    for (int t = 1; t <= max_target_; ++t) {
        const DropLattice& lattice = *lattices_[static_cast<std::size_t>(t)];
        if (t > 1 && lattices_[static_cast<std::size_t>(t - 1)].get() == &lattice && t < max_target_ &&
            lattices_[static_cast<std::size_t>(t + 1)].get() == &lattice)
            continue;   // the ends of a run of equal lattices cover it
        const double d_lo = 1e-3 * std::cbrt(t - 0.5), d_hi = std::min(config_.max_diameter, 1e-3 * std::cbrt(t + 0.5));
        for (double d : {d_lo, d_hi}) {
            if (!(d > 0.0)) continue;
            scratch.clear();
            const DropCalibration c = calibrate_drop(lattice, d, liquid, config_.options);
            add_drop(scratch, lattice, c, Vec3{}, Vec3{}, DragPreset::quadratic);
            scratch.set_integrator(config_.integrator);
            Body3DStability s;
            try {
                s = scratch.finalize(config_.time_step);
            } catch (const std::invalid_argument&) {
                s.sub_steps = 4097;
            }
            needs->emplace_back(d, s.sub_steps);
        }
    }
    std::lock_guard lock(cache.mutex);
    if (cache.needs.size() >= SubStepCache::limit) cache.needs.clear();
    return cache.needs.emplace(key, std::move(needs)).first->second;
}

int DropPool::add_liquid(const Liquid& liquid) {
    if (std::string why = validate(liquid); !why.empty()) throw std::invalid_argument("liquid '" + liquid.name + "': " + why);
    if (liquid_count() >= config_.max_liquids) throw std::invalid_argument("drop pool: no room for another liquid");
    // Every lattice at the two ends of its diameter range must run within max_sub_steps.
    for (const auto& [d, sub_steps] : *sub_step_needs(liquid))
        if (sub_steps > config_.max_sub_steps)
            throw std::invalid_argument("liquid '" + liquid.name + "': a " + std::to_string(d * 1e3) + " mm drop needs " +
                                        std::to_string(sub_steps) + " sub-steps per step (limit " +
                                        std::to_string(config_.max_sub_steps) + "): too viscous or too stiff for this time step");
    liquids_.push_back(liquid);
    return liquid_count() - 1;
}

void DropPool::set_retire_predicate(RetirePredicate done) {
    if (!done) throw std::invalid_argument("drop pool: empty retire predicate");
    done_ = std::move(done);
}

bool DropPool::spawn(double diameter, int liquid, Vec3 centre) {
    if (liquid < 0 || liquid >= liquid_count() || !(diameter > 0.0)) {
        ++stats_.rejected;
        return false;
    }
    const double speed = arrival_speed(diameter, liquids_[static_cast<std::size_t>(liquid)].density);
    return spawn(diameter, liquid, centre, Vec3{0.0, 0.0, -speed}, DragPreset::quadratic);
}

bool DropPool::spawn(double diameter, int liquid, Vec3 centre, Vec3 velocity, DragPreset drag) {
    if (liquid < 0 || liquid >= liquid_count() || !(diameter > 0.0) || diameter > config_.max_diameter ||
        !std::isfinite(centre.x + centre.y + centre.z + velocity.x + velocity.y + velocity.z)) {
        ++stats_.rejected;
        return false;
    }
    const int target = seed_mass_count(diameter);
    if (target > max_target_) {   // rounding at max_diameter itself
        ++stats_.rejected;
        return false;
    }
    if (free_.empty()) {
        ++stats_.refused;
        return false;
    }
    const int index = free_.back();
    free_.pop_back();
    Slot& s = slot(index);
    const DropLattice& lattice = *lattices_[static_cast<std::size_t>(target)];
    s.calibration = calibrate_drop(lattice, diameter, liquids_[static_cast<std::size_t>(liquid)], config_.options);
    s.body.clear();
    s.info = add_drop(s.body, lattice, s.calibration, centre, velocity, drag);
    s.body.finalize(config_.time_step);   // add_liquid checked the sub-steps: cannot throw
    s.drag = drag;
    s.liquid = liquid;
    s.dormant = true;   // whole, undeformed, one velocity
    s.shift = Vec3{};
    s.common = velocity;
    s.spawn_lowest_z = std::numeric_limits<double>::infinity();
    for (int m = 0; m < s.body.mass_count(); ++m) s.spawn_lowest_z = std::min(s.spawn_lowest_z, s.body.position(m).z);
    s.pieces = s.components.compute(s.body);
    s.steps = 0;
    s.coarse_left = 0;
    s.coarse_floor = coarse_floor_;
    s.serial = next_serial_++;
    active_.push_back(index);
    ++stats_.spawned;
    return true;
}

double DropPool::underside(double diameter) const {
    if (!(diameter > 0.0) || diameter > config_.max_diameter) return 0.0;
    const int target = seed_mass_count(diameter);
    if (target > max_target_) return 0.0;
    double lowest = 0.0;
    for (const Vec3& p : lattices_[static_cast<std::size_t>(target)]->shape.position)
        lowest = std::min(lowest, drop_orientation(p, config_.options.tilted).z);
    return -lowest * diameter;
}

bool DropPool::all_done(const Slot& s) const {
    if (s.dormant) {
        for (int m = 0; m < s.body.mass_count(); ++m)
            if (!done_(s.body.position(m) + s.shift, s.common)) return false;
        return true;
    }
    for (int m = 0; m < s.body.mass_count(); ++m)
        if (!s.body.is_frozen(m) && !done_(s.body.position(m), s.body.velocity(m))) return false;
    return true;
}

void DropPool::park_done_pieces(Slot& s) {
    const int n = s.body.mass_count();
    std::fill(s.piece_live.begin(), s.piece_live.begin() + n, std::uint8_t{0});
    bool any = false;
    for (int m = 0; m < n; ++m) {
        if (s.body.is_frozen(m)) continue;
        if (!done_(s.body.position(m), s.body.velocity(m)))
            s.piece_live[static_cast<std::size_t>(s.components.component_of(m))] = 1;
        else
            any = true;
    }
    if (!any) return;
    for (int m = 0; m < n; ++m) {
        if (s.body.is_frozen(m) || s.piece_live[static_cast<std::size_t>(s.components.component_of(m))]) continue;
        const Vec3 p = s.body.position(m);
        s.body.freeze(m, Vec3{p.x, p.y, p.z + config_.park_lift});
        ++stats_.parked;
    }
}

Vec3 DropPool::position(int drop, int mass) const {
    const Slot& s = slot(drop);
    return s.dormant ? s.body.position(mass) + s.shift : s.body.position(mass);
}

Vec3 DropPool::velocity(int drop, int mass) const {
    const Slot& s = slot(drop);
    return s.dormant ? s.common : s.body.velocity(mass);
}

Body3D& DropPool::awake(int drop) const {
    Slot& s = slot(drop);
    if (s.dormant) {
        s.dormant = false;
        for (int m = 0; m < s.body.mass_count(); ++m) {
            s.body.set_position(m, s.body.position(m) + s.shift);
            s.body.set_velocity(m, s.common);
        }
    }
    return s.body;
}

Body3D& DropPool::touched(int drop) {
    Slot& s = slot(drop);
    if (s.coarse_left > 0) {
        s.coarse_left = 0;   // steps from the next step() on, from where the coarse step left it
        ++stats_.coarse_interrupted;
    }
    return awake(drop);
}

void DropPool::step_dormant(Slot& s) const {
    // Body3D's symplectic Euler for one of the (identical) masses: F = m g - (c + b |v|) v,
    // v += dt F / m, x += dt v, per sub-step.
    const double m = s.body.mass(0), inv_m = 1.0 / m;
    const double c = s.body.linear_drag(0), b = s.body.quadratic_drag(0);
    const double dt = s.body.sub_step_time();
    const Vec3 g = config_.gravity;
    for (int k = 0; k < s.body.stability().sub_steps; ++k) {
        const Vec3 v = s.common;
        const double drag = c + b * std::sqrt(dot(v, v));
        const Vec3 f{m * g.x - drag * v.x, m * g.y - drag * v.y, m * g.z - drag * v.z};
        s.common = v + (dt * inv_m) * f;
        s.shift = s.shift + dt * s.common;
    }
}

void DropPool::release(std::size_t active_index) {
    free_.push_back(active_[active_index]);
    active_[active_index] = active_.back();
    active_.pop_back();
    ++stats_.retired;
}

void DropPool::set_coarse_floor(double z) {
    coarse_floor_ = z;
    for (const int d : active_) slot(d).coarse_floor = z;
}

void DropPool::retire(int drop) {
    for (std::size_t i = 0; i < active_.size(); ++i)
        if (active_[i] == drop) {
            release(i);
            return;
        }
}

void DropPool::clear() {
    while (!active_.empty()) release(active_.size() - 1);
}

void DropPool::set_changed_piece_drag(Slot& s) {
    // set_piece_drag (drop.hpp) for the changed pieces only: the same value, D (n / N)^(1/3)'s drag over n,
    // computed once per piece instead of once per mass. The other pieces keep theirs (it depends on their
    // size alone, which did not change).
    const ConnectedComponents& cc = s.components;
    if (s.drag != DragPreset::quadratic || cc.count() == 0) return;
    const double n_total = static_cast<double>(s.info.mass_count);
    for (const int piece : cc.changed()) {
        const int n = cc.size_of(piece);
        const double d_piece = s.calibration.diameter * std::cbrt(n / n_total);
        const double b = drag::drop_quadratic_drag(d_piece) / n;
        for (int i = 0; i < s.info.mass_count; ++i)
            if (cc.component_of(s.info.first_mass + i) == piece) s.body.set_quadratic_drag(s.info.first_mass + i, b);
    }
}

void DropPool::step() {
    const long max_steps = config_.max_lifetime > 0.0 ? std::lround(config_.max_lifetime / config_.time_step) : 0;
    // Each drop is checked every retire_interval of its own steps, counted from its spawn, not on a grid
    // shared by the pool: parking changes what is heard, so a drop must sound the same whenever it
    // starts (a drop alone and the same drop with another one timed after it are the same samples until
    // the second lands: tests/integration/bundle_timing_test.cpp).
    bool check = false;
    // Too old, or (at a check) all its masses done: the slot returns to the free list.
    auto finished = [&](const Slot& s) { return (max_steps > 0 && s.steps >= max_steps) || (check && all_done(s)); };
    // Backwards: release() moves the last active drop into the freed place.
    for (std::size_t i = active_.size(); i-- > 0;) {
        Slot& s = slot(active_[i]);
        ++s.steps;
        check = s.steps % config_.retire_interval == 0;
        if (s.dormant) {
            step_dormant(s);
            if (finished(s)) release(i);
            continue;
        }
        if (check && config_.park_done && s.coarse_left == 0) park_done_pieces(s);
        if (s.coarse_left > 0) {   // a coarse step covered this one (see the header)
            --s.coarse_left;
            ++stats_.coarse_sat_out;
            if (finished(s)) release(i);
            continue;
        }
        const int multiple = config_.coarse_max > 1 ? s.body.coarse_factor(config_.coarse_max, s.coarse_floor) : 1;
        if (multiple > 1) {
            ++stats_.coarse_steps;
            s.coarse_left = multiple - 1;
        }
        if (!s.body.step(multiple)) {   // the guard put the drop back as spawned: whole again
            s.coarse_left = 0;
            ++stats_.resets;
            s.pieces = s.components.compute(s.body);
        }
        if (!s.body.breaks().empty()) {
            stats_.link_breaks += static_cast<long>(s.body.breaks().size());
            // Only the pieces these breaks touched are searched, and only their masses get a new drag
            // (connected_components.hpp): a tear costs its neighbourhood, not the whole drop.
            const int pieces = s.components.update(s.body, s.body.breaks());
            if (pieces > s.pieces) {
                stats_.breakups += pieces - s.pieces;
                set_changed_piece_drag(s);
            }
            s.pieces = pieces;
        }
        if (finished(s)) release(i);
    }
}

}  // namespace ameoto
