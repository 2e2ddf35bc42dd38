// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Drop masses against the canopy's membrane masses: a two-body contact along the membrane's normal, wet
// (the default: each mass stopped as its parcel of liquid arrives, wet_impact.hpp) or the seed's
// exchange with restitution e (section 4.3; CollisionOptions::seed()).
//
// Interface (the audio thread may call what is marked so; construction and the rest from any one thread):
//   MembraneCollider collider(canopy, time_step_s, CollisionOptions::wet(rho));   // allocates
//   MembraneCollider collider(canopy, time_step_s, CollisionOptions::seed());     // the seed: e = 1
//   ---- every step, before stepping the canopy and the drops: never allocates ----
//   int n = collider.collide(canopy, masses);          // masses: any CollisionMasses (below)
//   int n = collider.collide(canopy, masses, [](const MembraneCollision& c) { ... });   // each collision
//   int n = collider.collide_drops(canopy, pool);      // pool: any CollisionDrops (below), e.g. DropPool
//   // or, for a caller that walks its own masses:
//   collider.begin_step();
//   Vec3 force; if (collider.collide_one(canopy, p, v, m, force)) body.apply_force(mass, force);
//   collider.collisions()                              // total so far
//
//   template <class M> concept CollisionMasses: m.count(), m.position(i) -> Vec3, m.velocity(i) -> Vec3,
//   m.mass(i) -> kg, m.apply_force(i, Vec3) (held for the next step, as Body3D::apply_force).
//   template <class P> concept CollisionDrops: the same indexed by drop and mass: p.active() (a range
//   of drop ids), p.mass_count(d), p.position(d, m), p.velocity(d, m), p.mass(d, m),
//   p.apply_force(d, m, Vec3) (the shape of models/drop_pool.hpp's DropPool, without depending on it).
//   MassArrays: a ready-made CollisionMasses over spans (positions, velocities, masses; forces added
//   into a span of Vec3).
// Order within a step: collide (forces for the next step), then step the canopy and the drops.
//
// Contact (seed 4.3, Fig. 9: a drop mass that lands between membrane masses collides with the nearest
// one). A drop mass at p with velocity v over plan point (x, y) of panel k, nearest node j
// (Canopy::locate), is at height
//   h = (p_z - z_rest(x, y)) n_z(x, y) - u_j
// above the membrane (the rest cap's normal distance, less the node's displacement u_j along its
// normal n_j). Normal speeds along n_j: v1 = v . n_j (drop), v2 = du_j/dt (node, plus what earlier
// collisions of this step gave it). It collides when it has reached the membrane moving into it:
//   h <= 0,  v1 - v2 < 0,  and  -h < T |v1 - v2| + skin.
// The last condition is the swept test: over the last step the pair closed by T |v1 - v2| (exact when
// the velocities are the step's backward differences, as in the CORDIS scheme and symplectic Euler), so
// a mass that crossed during the step is at most that deep, at any speed: nothing tunnels, however fast,
// as long as collide() runs every step. `skin` (1 mm, one drop-lattice spacing) keeps a mass that is
// still in contact (e.g. pushed by a rising membrane) from being let through; a mass deeper than that
// is under the canopy (the membrane is one-sided: drops come from above, along +n) and is ignored.
// Wet (model wet, the default): the same test with the mass's reach r (its parcel's radius,
// wet_impact.hpp) added to h, and the impulse of wet_impact.hpp's stopping law instead of the exchange
// below (e = 0 once the parcel's pulse is over). Everything else here (the node's pending velocity, the
// force held over one step, momentum exact) holds for both models.
// Seed exchange (model seed: 1-D two-body collision along n_j, frictionless: tangential components
// unchanged), with restitution e (1: elastic, the seed; < 1: loses energy):
//   v1' = ((m1 - e m2) v1 + (1 + e) m2 v2) / (m1 + m2),   v2' = ((m2 - e m1) v2 + (1 + e) m1 v1) / (m1 + m2)
// computed as the impulse J = -(1 + e) mu (v1 - v2), mu = m1 m2 / (m1 + m2): v1' = v1 + J / m1,
// v2' = v2 - J / m2, so the momenta m1 v1 + m2 v2 are equal to rounding, the kinetic energy is kept
// when e = 1 and falls by (1/2) mu (1 - e^2) (v1 - v2)^2 otherwise. The exchange acts as the seed's
// force over one step, f = m (v' - v) / T: (J / T) n_j on the drop mass, -J / T on the node along its
// normal (Canopy::apply_force); both bodies hold an applied force over exactly one output step T, so
// their velocities change by exactly J / m (for the node: plus its links' forces over that step).
// A node struck twice in one step uses the velocity the first collision gave it (sequential pairwise
// collisions), so energy is kept exactly then too.

#include <concepts>
#include <cstdint>
#include <iterator>
#include <span>
#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/wet_impact.hpp"

namespace ameoto {

template <class M>
concept CollisionMasses = requires(M& m, const M& c, int i, Vec3 f) {
    { c.count() } -> std::convertible_to<int>;
    { c.position(i) } -> std::convertible_to<Vec3>;
    { c.velocity(i) } -> std::convertible_to<Vec3>;
    { c.mass(i) } -> std::convertible_to<double>;
    m.apply_force(i, f);
};

template <class P>
concept CollisionDrops = requires(P& p, const P& c, int d, int m, Vec3 f) {
    { c.mass_count(d) } -> std::convertible_to<int>;
    { c.position(d, m) } -> std::convertible_to<Vec3>;
    { c.velocity(d, m) } -> std::convertible_to<Vec3>;
    { c.mass(d, m) } -> std::convertible_to<double>;
    p.apply_force(d, m, f);
    { *std::begin(c.active()) } -> std::convertible_to<int>;
    std::end(c.active());
};

struct MassArrays {
    std::span<const Vec3> positions, velocities;
    std::span<const double> masses;
    std::span<Vec3> forces;   // apply_force adds here

    int count() const { return static_cast<int>(positions.size()); }
    Vec3 position(int i) const { return positions[static_cast<std::size_t>(i)]; }
    Vec3 velocity(int i) const { return velocities[static_cast<std::size_t>(i)]; }
    double mass(int i) const { return masses[static_cast<std::size_t>(i)]; }
    void apply_force(int i, Vec3 f) { forces[static_cast<std::size_t>(i)] = forces[static_cast<std::size_t>(i)] + f; }
};

struct CollisionOptions {
    double restitution = 1.0;   // e, 0..1: 1 elastic (seed 4.3); the seed model's only
    double skin_m = 1e-3;       // contact depth kept beyond the swept depth
    ImpactModel model = ImpactModel::wet;               // wet_impact.hpp: wet (default) or the seed's exchange
    double liquid_density = constants::water_density;   // kg/m^3 (wet: each mass's parcel size)
    double max_reach_m = 1e-3;                           // m (wet: the reach's cap)

    static CollisionOptions seed(double e = 1.0) { return CollisionOptions{e, 1e-3, ImpactModel::seed}; }
    static CollisionOptions wet(double density = constants::water_density) {
        return CollisionOptions{1.0, 1e-3, ImpactModel::wet, density};
    }
    ContactLaw law() const { return ContactLaw{model, restitution, skin_m, liquid_density, max_reach_m}; }
};

struct MembraneCollision {
    int drop = -1, mass = -1;      // collide_drops: drop and mass; collide: mass (drop -1)
    int panel = -1, node = -1;
    Vec3 normal;                   // n_j, the line of the exchange
    double m1 = 0.0, m2 = 0.0;     // drop mass, membrane mass (kg)
    double v1 = 0.0, v2 = 0.0;     // normal speeds before (m/s)
    double v1_after = 0.0, v2_after = 0.0;
    double impulse = 0.0;          // J on the drop mass along n (N s); the node gets -J
    double depth = 0.0;            // -h (m) when detected
};

class MembraneCollider {
public:
    MembraneCollider(const Canopy& canopy, double time_step_s, const CollisionOptions& options = CollisionOptions{});

    void begin_step();
    // One drop mass (position p, velocity v, mass m): true if it collides; then `drop_force` is the force
    // to apply to it for the next step (the node's force is already applied), and `record` (if given)
    // describes the collision.
    bool collide_one(Canopy& canopy, Vec3 p, Vec3 v, double m, Vec3& drop_force, MembraneCollision* record = nullptr);

    template <CollisionMasses M>
    int collide(Canopy& canopy, M& masses) {
        return collide(canopy, masses, [](const MembraneCollision&) {});
    }

    template <CollisionMasses M, class Sink>
    int collide(Canopy& canopy, M& masses, Sink&& sink) {
        begin_step();
        int hits = 0;
        const int n = masses.count();
        for (int i = 0; i < n; ++i) {
            Vec3 force;
            MembraneCollision c;
            if (!collide_one(canopy, masses.position(i), masses.velocity(i), masses.mass(i), force, &c)) continue;
            masses.apply_force(i, force);
            c.mass = i;
            sink(static_cast<const MembraneCollision&>(c));
            ++hits;
        }
        return hits;
    }

    template <CollisionDrops P>
    int collide_drops(Canopy& canopy, P& pool) {
        return collide_drops(canopy, pool, [](const MembraneCollision&) {});
    }

    template <CollisionDrops P, class Sink>
    int collide_drops(Canopy& canopy, P& pool, Sink&& sink) {
        begin_step();
        int hits = 0;
        for (const int d : pool.active()) {
            const int n = pool.mass_count(d);
            for (int i = 0; i < n; ++i) {
                Vec3 force;
                MembraneCollision c;
                if (!collide_one(canopy, pool.position(d, i), pool.velocity(d, i), pool.mass(d, i), force, &c)) continue;
                pool.apply_force(d, i, force);
                c.drop = d;
                c.mass = i;
                sink(static_cast<const MembraneCollision&>(c));
                ++hits;
            }
        }
        return hits;
    }

    const CollisionOptions& options() const { return options_; }
    // m: how far above the membrane a mass of m kg is touched (0 for the seed; wet: its parcel's
    // radius, at most options().max_reach_m: what a broad phase must add to its bounds).
    double reach(double mass_kg) const { return law_.reach(mass_kg); }
    double time_step() const { return time_step_; }
    std::uint64_t collisions() const { return collisions_; }

private:
    CollisionOptions options_;
    ContactLaw law_;
    double time_step_ = 0.0;
    int nodes_per_panel_ = 0;
    // Per panel and node: the velocity this step's collisions gave it, valid where stamp_ == step_
    // (cleared lazily: begin_step() only moves step_ on).
    std::vector<double> pending_;
    std::vector<std::uint64_t> stamp_;
    std::uint64_t step_ = 1;
    std::uint64_t collisions_ = 0;
    double memo_mass_ = -1.0, memo_parcel_ = 0.0, memo_reach_ = 0.0;   // law_.parcel and reach of the last mass
};

}  // namespace ameoto
