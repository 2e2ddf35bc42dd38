// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A fixed-capacity pool of lattice drops (drop.hpp) for the audio thread: spawn, step, break up, retire,
// all without allocating.
//
// Interface:
//   DropPoolConfig config;                           // capacity, max diameter, time step, ...
//   DropPool pool(config);                           // allocates everything; builds the lattice of every
//                                                    // mass count up to the max diameter (cached per process)
//   ---- setup, off the audio thread ----
//   int water = pool.add_liquid(liquids::water());   // index; throws std::invalid_argument with a reason
//   pool.set_retire_predicate([](Vec3 p, Vec3 v) { return p.z < -0.1; });   // a mass is done when true
//   ---- audio thread: no allocation, no locks ----
//   bool ok = pool.spawn(D, water, centre);           // straight down at its arrival speed
//   bool ok = pool.spawn(D, water, centre, velocity, DragPreset::quadratic);
//   pool.step();                                      // every active drop, one time step
//   for (int d : pool.active())                       // slots of the active drops
//       for (int m = 0; m < pool.mass_count(d); ++m) {
//           pool.position(d, m); pool.velocity(d, m); pool.mass(d, m);
//           pool.apply_force(d, m, Vec3{...});          // held for the next step (collisions)
//       }
//   pool.pieces(d); pool.piece_of(d, m); pool.piece_size(d, p);   // what a drop has broken into
//   pool.dormant(d);                                  // falling whole, not yet touched (see below)
//   pool.parked(d, m);                                // taken out of the motion (Parking, below)
//   pool.lowest_z(d);                                 // m, no mass of the drop is lower (broad phase)
//   pool.body(d); pool.calibration(d); pool.serial(d); // its Body3D (wakes it), calibration, spawn number
//   pool.retire(d); pool.clear();
//   pool.set_coarse_floor(z);                         // m: drops wholly above may take coarse steps (below)
//   pool.set_coarse_floor(d, z);                      // m: the same for drop d alone (per-drop floors)
//   pool.stats();                                     // spawned, refused, rejected, retired, breaks, breakups
//   pool.underside(D);                                // m, centre to lowest mass (placing a drop on a surface)
//
// Storage: one Body3D per slot, reserved for the largest drop (masses and links), and one
// ConnectedComponents per slot. spawn() takes a free slot, clears its body (capacity kept), adds the
// drop from the shared lattice (unit-diameter positions and links, built at construction for every
// mass count that a diameter up to max_diameter gives) with the closed-form calibration of drop.hpp,
// and finalizes it: all within the reserved capacity. Liquids are a fixed table filled off the audio
// thread; add_liquid() also rejects a liquid whose drops would need more than max_sub_steps at the
// pool's time step (a very viscous liquid's dampers), so spawn() can never fail to finalize. That check
// builds and finalizes a drop at both ends of every lattice's diameter range; its answer is cached per
// process by what it depends on (max diameter, time step, liquid values, integrator, options), so the
// scene's many pools (one per impact template) pay for it once.
//
// Breakup: after a step in which links broke, the slot's components are updated for those links only
// (ConnectedComponents::update: a search around each broken link, no allocation); each increase of their
// number counts as breakups, and each changed piece gets the drag of a drop of its own volume (the value
// set_piece_drag gives, computed once per piece). Masses are never created or removed: a broken drop's pieces stay
// in its body, separate, until the drop retires (conservation is exact by construction).
//
// Dormant fall: a drop spawned whole, undeformed and with one velocity for all its masses feels no
// link force (each mass has the same weight and drag), so it falls as one: until anything touches it,
// step() moves one velocity and one shift (Body3D's symplectic Euler, per sub-step) instead of the
// lattice, exactly up to rounding. The first apply_force, set_position, set_velocity or body() wakes
// it: its masses are moved to where the shift says, at the common velocity, and from then on it is a
// full Body3D. position() and velocity() read a dormant drop without waking it. A collision module
// that applies forces only on contact thus pays for a drop's lattice only from its impact on.
//
// Retirement: every retire_interval of its own steps (counted from its spawn, so that a drop sounds
// the same whenever it starts) each active drop's masses are checked with the caller's predicate
// (default: z < retire_below); a drop whose masses are all done (at rest on a surface, or gone from the
// scene: the caller's choice) retires, as does one older than max_lifetime (a safety net;
// 0 = never). The slot returns to the free list.
//
// Parking (config.park_done; DropOnCanopy turns it on: drop_on_canopy.hpp, "Settling"): at the same
// checks, a piece of an awake drop (not sitting out a coarse step) whose every mass is done is parked:
// Body3D::freeze puts each of its masses park_lift (1 km) above where it was, at rest with 1/m = 0, so
// it no longer moves, touches anything, nor holds the drop's coarse steps and broad phase down with it;
// the rest of the drop carries on. A parked mass counts as done, and keeps its mass (conservation is
// unchanged), so the drop retires once every piece is parked or done. Whole pieces only: a parked
// mass has no intact bond to a moving one.
//
// Coarse steps (config.coarse_max > 1, and a floor set): an awake drop whose every mass is above the
// floor by more than it can travel takes k output steps as one (Body3D::coarse_factor() picks k, at
// most coarse_max: stable over the links that can act, clear of the floor; body3d.hpp, "Coarse steps")
// and then sits out the next k - 1 step() calls. Its masses show the state at the end of the coarse
// step meanwhile (at most k - 1 steps ahead). The caller sets the floor where nothing can touch a drop
// above it (drop_on_canopy_collide.cpp, each sample: the membrane's highest point read that sample plus 2 mm and
// the collider's skin, or the top of the 5 cm band the membrane never reaches): a splash's pieces in
// flight, most of a shattered drop's life, then cost a third or a quarter. The floor is held per drop:
// set_coarse_floor(z) sets every drop's, set_coarse_floor(d, z) one drop's (DropOnCanopy with settling
// sets each drop's from its own lowest mass, so that no drop's steps depend on another's).
// apply_force, set_position and set_velocity during the steps sat out end them (counted in
// stats().coarse_interrupted; the floor's margin means a collision never does). Default: off
// (coarse_max 1, floor +infinity).
//
// Cost: one Body3D step per active drop; measured in docs/drop.md ("Cost of a step").

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/connected_components.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/drop.hpp"
#include "engine/models/liquid.hpp"

namespace ameoto {

struct DropPoolConfig {
    int capacity = 16;                         // drops at once
    double max_diameter = 8e-3;                // m
    double time_step = 1.0 / 48000.0;          // s per step()
    int max_liquids = 8;
    int max_sub_steps = 8;                     // add_liquid refuses liquids that would need more
    int retire_interval = 32;                  // steps between retirement checks
    double retire_below = -1.0;                // m: the default predicate's floor
    double max_lifetime = 10.0;                // s (0: no limit)
    Vec3 gravity{0.0, 0.0, -constants::gravity};
    Integrator integrator = Integrator::symplectic_euler;
    DropOptions options;
    int coarse_max = 1;                        // output steps a drop in flight may take as one (1: never)
    bool park_done = false;                    // park each piece whose masses are all done (below)
    double park_lift = 1000.0;                 // m: how far above where it was a parked mass is put
};

struct DropPoolStats {
    long spawned = 0;
    long refused = 0;      // spawn() while full
    long rejected = 0;     // spawn() with a bad diameter or liquid index
    long retired = 0;
    long link_breaks = 0;  // links broken
    long breakups = 0;     // pieces gained (a drop that splits in three adds 2)
    long resets = 0;       // Body3D guard resets (never expected)
    long coarse_steps = 0;         // steps a drop took as k > 1 output steps
    long coarse_sat_out = 0;       // step() calls a drop sat out after a coarse step
    long coarse_interrupted = 0;   // coarse steps cut short by a force or a move (never expected)
    long parked = 0;               // masses parked (config.park_done)
};

class DropPool {
public:
    using RetirePredicate = std::function<bool(Vec3 position, Vec3 velocity)>;

    explicit DropPool(const DropPoolConfig& config = {});

    // ---- setup: off the audio thread ----
    int add_liquid(const Liquid& liquid);
    void set_retire_predicate(RetirePredicate done);

    // ---- audio thread ----
    bool spawn(double diameter, int liquid, Vec3 centre);
    bool spawn(double diameter, int liquid, Vec3 centre, Vec3 velocity, DragPreset drag = DragPreset::quadratic);
    void step();
    void retire(int drop);
    void clear();

    std::span<const int> active() const { return {active_.data(), active_.size()}; }
    int mass_count(int drop) const { return slot(drop).body.mass_count(); }
    Vec3 position(int drop, int mass) const;
    Vec3 velocity(int drop, int mass) const;
    double mass(int drop, int mass) const { return slot(drop).body.mass(mass); }
    void apply_force(int drop, int mass, Vec3 force) { touched(drop).apply_force(mass, force); }
    void set_position(int drop, int mass, Vec3 p) { touched(drop).set_position(mass, p); }
    void set_velocity(int drop, int mass, Vec3 v) { touched(drop).set_velocity(mass, v); }
    // m (+infinity: no coarse steps): every active drop's floor, and the floor a drop spawned later starts with.
    void set_coarse_floor(double z);
    // m: drop d's own floor, until it is set again (a caller whose floor differs by drop: each drop's coarse
    // steps then depend on its own state and on what the caller reads for it, never on the other drops).
    void set_coarse_floor(int drop, double z) { slot(drop).coarse_floor = z; }
    double coarse_floor() const { return coarse_floor_; }
    double coarse_floor(int drop) const { return slot(drop).coarse_floor; }
    Body3D& body(int drop) { return awake(drop); }
    const Body3D& body(int drop) const { return awake(drop); }
    bool dormant(int drop) const { return slot(drop).dormant; }
    // Parked (config.park_done): taken out of the motion, position() park_lift above where it was.
    bool parked(int drop, int mass) const { return !slot(drop).dormant && slot(drop).body.is_frozen(mass); }
    // m: no mass of the drop lies lower (a lower bound for a broad phase; -infinity when unknown: just
    // woken or reset). Awake: Body3D::lowest_z(); dormant: the lowest mass at spawn plus the shift, which
    // is exactly the lowest of position(drop, m) (rounding x + s is monotonic in x). Does not wake it.
    double lowest_z(int drop) const {
        const Slot& s = slot(drop);
        return s.dormant ? s.spawn_lowest_z + s.shift.z : s.body.lowest_z();
    }
    const DropCalibration& calibration(int drop) const { return slot(drop).calibration; }
    int liquid_of(int drop) const { return slot(drop).liquid; }
    std::uint64_t serial(int drop) const { return slot(drop).serial; }   // 1, 2, ... in spawn order
    double age(int drop) const { return static_cast<double>(slot(drop).steps) * config_.time_step; }
    int pieces(int drop) const { return slot(drop).pieces; }
    int piece_of(int drop, int mass) const { return slot(drop).components.component_of(mass); }
    int piece_size(int drop, int piece) const { return slot(drop).components.size_of(piece); }

    // ---- queries ----
    const DropPoolConfig& config() const { return config_; }
    int capacity() const { return config_.capacity; }
    int max_masses() const { return max_masses_; }
    int liquid_count() const { return static_cast<int>(liquids_.size()); }
    const Liquid& liquid(int index) const { return liquids_[static_cast<std::size_t>(index)]; }
    const DropPoolStats& stats() const { return stats_; }
    const DropLattice& lattice(int target_masses) const { return *lattices_[static_cast<std::size_t>(target_masses)]; }
    // m: how far the lowest mass of a drop of this diameter lies below its centre (the lattice's own
    // extent, under D / 2); 0 for a diameter the pool cannot spawn. No allocation.
    double underside(double diameter) const;
    // How many add_liquid checks the process holds (keyed by liquid, step, size and integrator; at
    // most 32, then the cache starts again, so a live sweep of custom liquids cannot grow it).
    static std::size_t cached_liquid_checks();

private:
    struct Slot {
        // Dormant (see the header): the body still holds the positions at spawn; the drop is at
        // those + shift, every mass moving at `common`.
        bool dormant = false;
        Vec3 shift{}, common{};
        double spawn_lowest_z = 0.0;   // m, the body's lowest z as spawned (lowest_z())
        Body3D body;
        ConnectedComponents components;
        DropCalibration calibration;
        DropInfo info;
        DragPreset drag = DragPreset::quadratic;
        int liquid = 0;
        int pieces = 0;
        long steps = 0;
        std::uint64_t serial = 0;
        int coarse_left = 0;   // step() calls to sit out after a coarse step
        double coarse_floor = std::numeric_limits<double>::infinity();   // m: its coarse steps' floor
        std::vector<std::uint8_t> piece_live;   // parking's scratch: per piece, a mass not done
    };
    Slot& slot(int drop) const { return slots_[static_cast<std::size_t>(drop)]; }
    Body3D& awake(int drop) const;   // wakes a dormant drop (no allocation; the physics is unchanged)
    Body3D& touched(int drop);       // awake(), and ends a coarse step's sitting out
    void step_dormant(Slot& s) const;
    void set_changed_piece_drag(Slot& s);
    bool all_done(const Slot& s) const;
    void park_done_pieces(Slot& s);
    // add_liquid's check: (diameter, sub-steps needed) for each end of each lattice's diameter range,
    // cached per process by everything the answer depends on (drop_pool.cpp).
    std::shared_ptr<const std::vector<std::pair<double, int>>> sub_step_needs(const Liquid& liquid) const;
    void release(std::size_t active_index);

    DropPoolConfig config_;
    std::vector<std::shared_ptr<const DropLattice>> lattices_;   // by target mass count, 1..max
    std::vector<Liquid> liquids_;
    mutable std::vector<Slot> slots_;   // mutable: reading a dormant drop's body wakes it
    std::vector<int> active_, free_;
    RetirePredicate done_;
    DropPoolStats stats_;
    std::uint64_t next_serial_ = 1;
    int max_masses_ = 0;
    int max_target_ = 0;
    double coarse_floor_ = std::numeric_limits<double>::infinity();
};

}  // namespace ameoto
