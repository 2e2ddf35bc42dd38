// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A CORDIS-ANIMA mass-interaction body in 3-D: point masses joined by links that have a rest length,
// some of them breakable, under gravity and air drag. Structure-of-arrays storage.
//
// Interface:
//   Body3D body;                                              // build phase (allocates)
//   int m = body.add_mass(mass_kg, Vec3{x, y, z});
//   int f = body.add_fixed_point(Vec3{...});                  // never moves, infinite mass
//   int l = body.add_spring(a, b, k, z, rest_length);         // spring-damper along the link axis
//   body.add_contact(a, b, k, z, rest_length);                // pushes only while |d| < rest_length
//   body.add_breakable(a, b, k, z, rest_length, break_force); // spring-damper that breaks at |F| > threshold
//   body.add_cohesive(a, b, k, z, rest_length, break_force, core_length, core_k);   // a liquid's bond
//   body.set_gravity(Vec3{0, 0, -9.80665});
//   body.set_linear_drag(m, c);                               // -c v, N s/m (seed: 1.77e-8, body3d_drag.hpp)
//   body.set_quadratic_drag(m, b);                            // -b |v| v, b = rho_air C_d A / 2, kg/m
//   body.set_integrator(Integrator::explicit_verlet | Integrator::symplectic_euler);   // false for others
//   body.set_energy_limit(joules);                            // runtime guard (default: non-finite only)
//   Body3DStability s = body.finalize(T);                     // bound, sub-steps; allocates the event list
//   body.reserve(masses, links); body.clear();                // for reuse: within the reserved capacity,
//                                                             // clear, add_* and finalize never allocate
//   ---- render phase: never allocates ----
//   body.apply_force(m, Vec3{...});                           // external force for the next step
//   bool ok = body.step();                                    // one output step (all sub-steps); false if
//                                                             // the guard reset the body (or if the body
//                                                             // was not finalized: then it does nothing)
//   int k = body.coarse_factor(max_k, floor_z);               // how many output steps may be taken as one
//   body.step(k);                                             // k output steps as one (a coarse step)
//   for (const LinkBreak& e : body.breaks()) ...              // links that broke during that step
//   body.set_position(m, p); body.set_velocity(m, v); body.reset();
//   body.freeze(m, p); body.is_frozen(m)                      // out of the motion for good (1/m = 0, mass kept)
//   body.position(m), velocity(m), momentum(), energy(), resets(), link_broken(l), stability(),
//   body.positions()                                          // .x .y .z: every mass's coordinates
//   body.lowest_z()                                           // the lowest mass's z after the last step
//   linear_drag(m), quadratic_drag(m) ...
//   body.set_portable_kernels(true);                          // the scalar step even on AVX2 (tests)
//   body.avx2_kernels();                                      // which code finalize() picked
//
// Links (seed section 4.1, in 3-D): d = x1 - x2, L = |d|, u = d / L. The link acts along its axis only:
//   F1 = -F2 = s u,   s = -k (L - l0) - z ((v1 - v2) . u)
// (CORDIS-ANIMA's F1 = -F2 = -k((x1 - l1) - (x2 - l2)) - z (v1 - v2), with the rest length measured
// along the axis and the damper acting on the axial relative speed only, so a link never resists
// rotation of the pair). At L = 0 the axis is undefined and the link exerts no force.
//   - spring: always acts.
//   - contact (unilateral, a penalty force for collisions): acts only while L < l0, and only pushes:
//     s = max(0, s), so its damper never glues two masses together.
//   - breakable (seed section 4.4): a spring-damper; in the sub-step where |s| first exceeds its
//     break force the link breaks instead of acting. The break is recorded as a LinkBreak event in a
//     fixed-capacity list (capacity = number of breakable links: a link breaks once, so the list
//     cannot overflow within one step), cleared at the start of each step() and read after it. A
//     broken link keeps its slot and a flag, and is skipped from then on; nothing is erased.
//   - cohesive (a liquid's bond, engine/models/drop.hpp): a spring-damper bond s_b = -k (L - l0) - z v_ax
//     that breaks only when its spring pulls harder than its threshold, k (L - l0) > break force
//     (surface tension resists being torn apart; compression never breaks it, and the damper, the
//     liquid's viscosity, resists the stretching without counting towards the tear), plus a repulsive
//     core that pushes while L < core length, s_c = k_c (l_c - L) > 0, before and after the bond
//     breaks (the liquid's resistance to compression: broken neighbours collide instead of passing
//     through each other). s = s_c + s_b while bonded, s = s_c once broken. The event's force is the
//     spring's, -k (L - l0).
// Internal links exert equal and opposite forces, so they conserve momentum (to rounding).
//
// Vectorisation (the scalar reference and the AVX2 kernels side by side: body3d_step_scalar.cpp and
// body3d_step_avx2.cpp, body3d_links_scalar.cpp and body3d_links_avx2.cpp; body3d_sparse_links.cpp).
// finalize() picks one of two steps: on a CPU with AVX2, for a body of 16 masses or more, kernels
// compiled for AVX2 whatever the build's target, written on 4-lane vectors (GCC vector extensions);
// otherwise (or after set_portable_kernels(true)) the scalar step, which is the reference. (The
// same vector code built for baseline x86-64, two 128-bit halves per vector, ran 4 times slower than the
// scalar step.)
//   1. per mass, four masses at a time: velocities (CORDIS), gravity, drag, external forces;
//   2. the links. Any body: generic_links(), a scalar loop that adds s u to a and -s u to b in link
//      order. A body whose links are all cohesive with one set of parameters (a drop): four links at a
//      time, their masses read from a mirror written in 1. (position and velocity, one 64-byte row per
//      mass) and transposed into lanes. While at least a quarter of the links are bonded ("dense") it
//      computes every link, and each writes +s u and -s u for 3. to add per mass in link order; once
//      most are broken ("sparse") it computes only candidates, in link order, and adds their forces
//      lane after lane. The candidates are the bonded links and the broken ones whose masses were
//      within core length + 4 h (h: the rest length) when listed; the list is made again once any two
//      masses may have approached by 2 h (bounded by the range of the masses' displacements since,
//      which the sparse step's update measures for the next sub-step as it writes the positions), so
//      every link left out is one the scalar pass skips (broken, core not touching). A full listing
//      looks at every link and keeps aside those within core length + 32 h (and the bonded ones); the
//      listings after it look at those only, until the sum of the listings' bounds (which bounds the
//      approach since the full listing) passes 28 h;
//   3. per mass, four at a time: the dense pass's link forces, then the update.
// A 5 mm drop per 48 kHz step, scalar -> AVX2 (docs/drop.md, "Cost of a step"): awake 5.6 -> 3.1 us,
// shattered 1.8 -> 0.81 us.
// Bit identity. The AVX2 step gives the scalar step's result to the bit, so a render is the same on any
// x86-64: each lane performs the same IEEE operations in the same order (+, -, *, /, sqrt are correctly
// rounded whatever the vector width; no FMA: AVX2 does not include it and every body3d_*.cpp is built
// with -ffp-contract=off; nothing is reassociated); branches become lane masks; every force reaches its
// mass's accumulator in link order, as in the scalar pass, and a link that adds nothing there adds
// -0.0 here, which leaves any sum unchanged (x + -0 = x for every x, -0 included); the energies, which
// cross lanes, are added lane by lane in the scalar order; the guard's position sum is kept as four
// partial sums, masses i = k mod 4 in sum k (lane k here, sum[i % 4] in the scalar step), added
// together at the end (no chain of dependent adds through every mass). Tested every step on a
// shattering drop (dense and sparse): AVX2 uniform pass, scalar uniform pass, AVX2 per-mass kernels
// with the generic pass.
//
// Coarse steps (a body in flight; drop_pool.hpp uses them for a splash over the membrane). step(k) takes
// k output steps as one: symplectic Euler with the time step k T' (T' the sub-step), the same kernels
// and operations with a longer step, so the AVX2 and scalar steps still agree to the bit, and step(1)
// is step() exactly (T' x 1.0 = T'); with CORDIS (whose state is x[n-1], tied to T'), k ordinary steps
// one after another. An external force acts over the whole of it. coarse_factor(max_k, floor_z) says
// which k (1..max_k) keeps the body stable and clear of the floor (drop_pool.hpp's "coarse steps"):
//   - stable: Gershgorin as finalize(), but over what can act within the step: intact links' springs
//     and dampers; of the broken links only cores (k_c) and contacts whose masses are within their
//     length + coarse_reach (16 rest lengths) of touching at the last look; and an intact cohesive
//     link's own core only if its masses could come closer than the core's length within the step,
//     at 1.5 x their relative speed and the largest acceleration their bonds can give them (a bond's
//     masses move nearly together, and its core, in a drop 1 450 times stiffer than its spring, is
//     what limits k); the others are clear for a time computed with them, and checked again after it.
//     The largest k <= max_k with margin (omega^2 (k T')^2 + 2 gamma k T') / 4 < 0.9, as finalize()
//     picks sub-steps;
//   - a look (a pass over the masses for the fastest speed, one over the links) takes a speed bound:
//     1.5 x the fastest mass's speed plus 1 m/s (head-room for what a piece's own links turn into
//     speed), plus gravity's gain since; two masses approach at most twice that. The links are looked
//     at again once they may have approached by coarse_reach since the last look, counting the step to
//     come (at a splash's 6-9 m/s and 4 rest lengths of about a millimetre: every 10 or so samples at
//     48 kHz). New breaks only remove stiffness, so they need no new look;
//   - clear of the floor: the lowest mass (lowest_z(), from the last step) above floor_z by more than
//     the step's travel at that speed bound;
//   - 1 (no coarse step) for CORDIS, a body not finalized, an unknown lowest mass (after set_position,
//     reset, finalize), or an external force applied for the step to come.
//
// External forces per mass: gravity m g, linear drag -c v (the seed's model, section 4.5), quadratic
// drag -b |v| v with b = rho_air C_d A / 2 (body3d_drag.hpp gives C_d and b for water drops), and
// apply_force(), which is held over the sub-steps of one step() and then cleared.
//
// Integrators (selectable per body; the engine's Integrator enum, integrators/integrator.hpp; Body3D
// runs its two explicit schemes: the implicit and modal ones need a fixed linear system, which a body
// whose links break and make contact is not):
//   explicit_verlet:  x[n+1] = 2 x[n] - x[n-1] + T^2 F / m, with v[n] = (x[n] - x[n-1]) / T in the
//                     dampers and drag (the CORDIS explicit scheme, as in transverse_network.cpp).
//   symplectic_euler: v[n+1] = v[n] + T F(x[n], v[n]) / m;  x[n+1] = x[n] + T v[n+1].
// In exact arithmetic the two give the same trajectory: substituting v[n] = (x[n] - x[n-1]) / T into
// symplectic Euler gives the CORDIS update. They differ in what is stored: CORDIS keeps x[n-1] and
// recovers v by a difference of positions, which loses eps |x| / T of velocity each step; symplectic
// Euler keeps v, which loses only eps |v|. So symplectic Euler conserves momentum far more tightly and
// gives velocities without cancellation, at no extra cost. Both share one stability condition.
//
// Stability (physics.md section 3): per mode, stable iff omega^2 T^2 + 2 gamma T < 4 (the Jury test
// on z^2 - (2 - w^2T^2 - gT) z + (1 - gT), the same characteristic polynomial for both schemes).
// omega_max^2 and gamma_max are bounded with Gershgorin on M^-1 K and M^-1 C, block by block: the 3x3
// stiffness block of a link has eigenvalues k (along the axis) and k (1 - l0 / L) (across it), both at
// most k in magnitude while L >= l0 / 2, so a link adds k to each end's diagonal and k off it: a link
// to another free mass counts twice, a link to a fixed point once (as an anchor in
// transverse_network.cpp). Contact links count as if active; a cohesive link counts k + k_c (its core
// as if active; the core's block is bounded the same way while L >= l_c / 2). gamma adds link dampers the same way,
// linear drag c / m, and quadratic drag linearised at a speed bound: d(b|v|v)/dv = 2 b |v| / m at
// |v| = speed_bound (default 20 m/s, twice a raindrop's terminal speed; set_speed_bound()). finalize()
// picks the fewest sub-steps with margin (omega^2 T'^2 + 2 gamma T') / 4 < 0.9 and refuses (throws)
// beyond 4096. finalize(T, n) forces n sub-steps (for tests, or for a caller that accepts the guard);
// the report's stable() then says whether that is safe.
//
// Runtime guard: after each step, if any position is non-finite or the body's energy (kinetic plus
// the links' elastic energy; gravity's potential is left out because a falling body's is unbounded)
// exceeds the caller's limit, the body is reset (every mass back to its position at finalize(), zero
// velocity, all links intact) and resets() increments: a diverging body is muted and counted, never
// left to explode. The energy is the one the step measured, at the start of its last sub-step (no extra
// pass over the links), and only when a limit is set: by default (no limit) no energy is summed, since
// its sums are a chain of dependent adds through every mass and link, and the non-finite check reads
// the position sum alone (a NaN or Inf velocity reaches the positions at the next update). So the
// guard lags by one sub-step: a stable body cannot grow much in one sub-step, and an unstable one
// (forced sub-steps) is let through at most one sub-step's growth past the limit. Positions are
// checked after the last update.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/core/integrators/integrator.hpp"

namespace ameoto {

enum class LinkKind : std::uint8_t { spring, contact, breakable, cohesive };

struct Body3DStability {
    double omega_max_bound = 0.0;   // rad/s, Gershgorin upper bound
    double gamma_max_bound = 0.0;   // 1/s, damping rate bound
    double time_step = 0.0;         // s, the caller's output step
    int sub_steps = 1;              // internal steps per output step
    double margin() const;          // (omega^2 T'^2 + 2 gamma T') / 4 at the chosen sub-step
    bool stable() const { return margin() < 1.0; }
};

// One link that broke during the last step().
struct LinkBreak {
    std::int32_t link = 0;
    std::int32_t a = 0, b = 0;   // its masses
    double force = 0.0;          // N, the axial force that broke it (positive: pushing a and b apart)
    std::int32_t sub_step = 0;   // which sub-step of the step
};

namespace body3d_avx2 {
struct StepView;   // the AVX2 kernels' view of a body (body3d_avx2.hpp, private)
}

class Body3D {
public:
    static constexpr double no_break = std::numeric_limits<double>::infinity();

    // ---- build phase ----
    int add_mass(double mass_kg, Vec3 position);
    int add_fixed_point(Vec3 position);
    int add_link(int a, int b, LinkKind kind, double stiffness, double damping, double rest_length,
                 double break_force = no_break);
    int add_spring(int a, int b, double k, double z, double rest_length) {
        return add_link(a, b, LinkKind::spring, k, z, rest_length);
    }
    int add_contact(int a, int b, double k, double z, double rest_length) {
        return add_link(a, b, LinkKind::contact, k, z, rest_length);
    }
    int add_breakable(int a, int b, double k, double z, double rest_length, double break_force) {
        return add_link(a, b, LinkKind::breakable, k, z, rest_length, break_force);
    }
    // A liquid's bond (see the header): breaks under tension only; its core (stiffness core_k, N/m)
    // pushes while the masses are closer than core_length (m), bonded or not. core_k = 0: no core.
    int add_cohesive(int a, int b, double k, double z, double rest_length, double break_force, double core_length,
                     double core_k);
    void set_gravity(Vec3 g) { gravity_ = g; }
    void set_linear_drag(int mass, double c_n_s_per_m);
    void set_quadratic_drag(int mass, double b_kg_per_m);
    void set_speed_bound(double m_per_s) { speed_bound_ = m_per_s; }
    void set_energy_limit(double joules) { energy_limit_ = joules; }

    // Capacity for reuse (allocates once): afterwards clear() and up to `masses` add_mass /
    // add_fixed_point, up to `links` add_* links and finalize() run without allocating.
    void reserve(int masses, int links);
    // Removes every mass and link (capacity kept) and the counters (resets, dropped breaks); keeps the
    // settings: gravity, integrator, speed bound, energy limit. The body must be finalized again.
    void clear();

    // Bounds omega_max and gamma_max, picks sub-steps (or takes forced_sub_steps > 0), records the
    // current positions as the state reset() returns to, sizes the event list. Allocates.
    const Body3DStability& finalize(double time_step_s, int forced_sub_steps = 0);

    // ---- render phase: no allocation ----
    bool set_integrator(Integrator integrator);   // any time; state carries over; false (and no change)
                                                  // for a scheme Body3D does not run
    void apply_force(int mass, Vec3 newtons);
    bool step(int time_multiple = 1);             // time_multiple output steps as one (see "Coarse steps")
    int coarse_factor(int max_multiple, double floor_z);   // 1..max_multiple (see "Coarse steps")
    bool external_forces_pending() const { return external_forces_; }   // apply_force() since the last step
    std::span<const LinkBreak> breaks() const { return {events_.data(), event_count_}; }
    void set_position(int mass, Vec3 p);          // keeps the mass's velocity
    void set_velocity(int mass, Vec3 v);          // ignored for fixed points
    // Takes a mass out of the motion for good (DropPool's parking of liquid that is done: drop_pool.hpp):
    // moves it to `at` at rest and gives it 1/m = 0, so no force moves it again (both schemes leave it
    // where it is, as a fixed point), while it keeps its mass (mass(), total_mass(): conservation) and
    // its links (a parked piece's own bonds hold; any link to a moving mass keeps acting on that mass
    // alone). reset() and clear() undo it. Ignored for fixed points.
    void freeze(int mass, Vec3 at);
    bool is_frozen(int m) const { return inv_mass_[idx(m)] == 0.0 && fixed_[idx(m)] == 0; }
    void reset();

    // ---- queries ----
    int mass_count() const { return static_cast<int>(x_.size()); }
    int link_count() const { return static_cast<int>(link_a_.size()); }
    Integrator integrator() const { return integrator_; }
    Vec3 position(int m) const;
    Vec3 velocity(int m) const;                   // CORDIS: backward difference over the last sub-step
    // Every mass's coordinates as arrays (mass_count() each): position(m) is {x[m], y[m], z[m]}. For a
    // caller that scans every mass each step (the collision broad phase, drop_on_canopy_collide.cpp) without a
    // call per mass. Valid until the body is cleared or built again.
    struct Coordinates {
        const double *x, *y, *z;
    };
    Coordinates positions() const { return {x_.data(), y_.data(), z_.data()}; }
    // The lowest z of any mass (fixed points included) as the last step() left them, measured by its
    // update (no pass of its own; the same value on either step), for a broad phase that skips a whole
    // body at once (drop_on_canopy_collide.cpp). -infinity (unknown: skip nothing) after finalize(), reset(),
    // set_position(), or a step the guard reset.
    double lowest_z() const { return lowest_z_; }
    double mass(int m) const { return mass_[idx(m)]; }   // 0 for a fixed point
    double linear_drag(int m) const { return linear_drag_[idx(m)]; }
    double quadratic_drag(int m) const { return quadratic_drag_[idx(m)]; }
    bool is_fixed(int m) const { return fixed_[idx(m)] != 0; }
    double total_mass() const;
    Vec3 centre_of_mass() const;
    Vec3 momentum() const;                        // sum of m v over free masses
    double kinetic_energy() const;
    double elastic_energy() const;                // sum of k (L - l0)^2 / 2 over acting links and
                                                  // k_c (l_c - L)^2 / 2 over acting cores
    double energy() const { return kinetic_energy() + elastic_energy(); }
    int link_a(int l) const { return link_a_[idx(l)]; }
    int link_b(int l) const { return link_b_[idx(l)]; }
    LinkKind link_kind(int l) const { return kind_[idx(l)]; }
    double rest_length(int l) const { return rest_[idx(l)]; }
    bool link_broken(int l) const { return broken_[idx(l)] != 0; }
    int broken_link_count() const;
    // True if the link holds its masses together as one piece (for connected_components.hpp): an
    // unbroken spring, breakable or cohesive link. Contacts (and broken cohesive links' cores) touch,
    // they do not bind.
    bool link_bonds(int l) const { return !link_broken(l) && kind_[idx(l)] != LinkKind::contact; }
    const Body3DStability& stability() const { return stability_; }
    double sub_step_time() const { return sub_dt_; }
    long resets() const { return resets_; }
    long dropped_breaks() const { return dropped_breaks_; }   // events lost to a full list (never expected)

    // Which code runs the step: the AVX2 kernels (chosen at finalize() when the CPU has AVX2 and the
    // body 16 masses or more) or the scalar step. They give the same result to the bit (see the
    // header); this forces the scalar step, for the test that checks it. Takes effect at the next
    // finalize().
    void set_portable_kernels(bool on) { portable_kernels_ = on; }
    bool avx2_kernels() const { return use_avx2_; }

private:
    static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
    void sub_step(int index);              // sub_step_avx2() or sub_step_baseline() (finalize() picks)
    void sub_step_avx2(int index);         // the vectorised kernels (body3d_step_avx2.cpp)
    void sub_step_baseline(int index);     // scalar: the reference (body3d_step_scalar.cpp)
    double generic_links(int index);       // the link pass for any links (scalar; body3d_links_scalar.cpp)
    double uniform_cohesive_links(int index);   // the baseline's link pass for uniform cohesive links (ditto)
    double sparse_links_pass(body3d_avx2::StepView& s);   // the AVX2 sparse pass (body3d_sparse_links.cpp)
    void build_link_scratch();             // finalize(): the uniform pass's lists and scratch (body3d_build.cpp)
    void check_link_args(int a, int b) const;
    void look_at_links();                  // coarse_factor()'s look at the links (body3d_coarse.cpp)
    void check_bonds(double step_s);       // ... and at the bonds' cores (body3d_coarse.cpp)
    void gershgorin_maxima(double& omega2, double& gamma) const;   // from k_sum_, z_sum_ (finalize, looks)

    // masses (structure of arrays)
    std::vector<double> x_, y_, z_;          // position, m
    std::vector<double> px_, py_, pz_;       // position one sub-step earlier
    std::vector<double> vx_, vy_, vz_;       // velocity (state for symplectic Euler; scratch for CORDIS)
    std::vector<double> fx_, fy_, fz_;       // force accumulator
    std::vector<double> ex_, ey_, ez_;       // external force for the current step
    std::vector<double> x0_, y0_, z0_;       // positions reset() returns to
    std::vector<double> mass_, inv_mass_;    // 0 and 0 for fixed points
    std::vector<double> linear_drag_, quadratic_drag_;
    std::vector<std::uint8_t> fixed_;
    // links
    std::vector<std::int32_t> link_a_, link_b_;
    std::vector<double> stiffness_, damping_, rest_, break_force_;
    std::vector<double> core_length_, core_stiffness_;   // cohesive links only (0 for the others)
    std::vector<LinkKind> kind_;
    std::vector<std::uint8_t> broken_;
    // finalize()'s scratch (members so that a reserved body finalizes without allocating)
    std::vector<double> k_sum_, z_sum_;
    // The uniform cohesive pass's scratch (sized by finalize() within reserve()'s capacity; the arrays
    // of doubles get 8 spare elements so that their working part can start on a 64-byte boundary):
    std::vector<double> mirror_;                 // per mass x y z 0 vx vy vz 0 (64 bytes), sub-step start
    std::vector<double> contribution_;           // per link +t and -t (x y z 0 each), then -0.0 x 4
    std::vector<std::int32_t> slots_;            // per group of 4 masses: its contributions, in link order
    std::vector<std::int32_t> slot_start_;       // per group: where its slots start (groups + 1 entries)
    std::vector<std::int32_t> degree_;           // per mass, build_link_scratch()'s count
    std::vector<std::int32_t> link_ends_;        // per link 8 a, 8 b: its masses' rows in the mirror
    std::vector<std::int32_t> candidates_;       // the sparse pass's links, in order (sparse_links_pass())
    std::vector<std::int32_t> near_links_;       // what a partial listing looks at, in order
    std::size_t near_link_count_ = 0;
    double far_travel_ = 0.0;                    // m, the approach bound since the last full listing
    static constexpr double far_margin = 32.0;   // h: a full listing's near links (sparse_links_pass())
    static constexpr double near_margin = 4.0;   // h: a candidate's margin, listed again after half of it
    std::vector<double> listed_x_, listed_y_, listed_z_;   // the positions they were listed at
    std::size_t candidate_count_ = 0;
    bool candidates_valid_ = false;
    double next_bound2_ = 0.0;         // the approach bound of the positions the last update wrote
    bool next_bound_fresh_ = false;    // ... and no mass has been moved since (sparse_links_pass())
    // events
    std::vector<LinkBreak> events_;
    std::size_t event_count_ = 0;
    std::size_t broken_count_ = 0;   // broken links (kept by the passes, reset(), finalize())

    Vec3 gravity_{};
    Integrator integrator_ = Integrator::explicit_verlet;
    double speed_bound_ = 20.0;
    double energy_limit_ = std::numeric_limits<double>::infinity();
    Body3DStability stability_;
    double sub_dt_ = 0.0;
    double last_energy_ = 0.0;       // measured during the last sub-step, for the guard
    double last_position_sum_ = 0.0; // sum of all coordinates after the last sub-step (finite check)
    double lowest_z_ = -std::numeric_limits<double>::infinity();   // lowest_z()
    double dt_scale_ = 1.0;          // step(k): k for the sub-steps of a coarse step, else 1
    // coarse_factor()'s look at the links (body3d_coarse.cpp): the positions it was made at and its answer.
    static constexpr double coarse_reach = 16.0;   // rest lengths: how near a broken link counts as acting
    static constexpr int coarse_limit = 64;       // the largest multiple looked for
    bool coarse_looked_ = false;
    double coarse_omega2_ = 0.0;     // 1/s^2, the look's Gershgorin bound, bonds' cores left out
    double coarse_gamma_ = 0.0;      // 1/s, the look's damping bound
    std::vector<std::int32_t> coarse_bonds_;   // intact cohesive links with a core, at the look
    std::vector<double> core_extra_;           // per mass scratch (zero between calls)
    std::vector<std::int32_t> touched_;        // the masses check_bonds() wrote there
    double bond_accel_ = 0.0;        // m/s^2, how fast a bond's masses can speed towards each other
    bool bonds_checked_ = false;
    double bonds_omega2_ = 0.0;      // 1/s^2, the look's bound with the bonds' cores that may engage
    double bonds_clear_for_ = 0.0;   // s, from the check: how long the others stay clear
    double since_bonds_ = 0.0;       // s stepped since the check
    double look_speed_ = 0.0;        // m/s, the speed bound taken at the last look
    double since_look_ = 0.0;        // s stepped since the last look
    double coarse_reach_m_ = 0.0;    // m, coarse_reach x the longest rest length (finalize())
    bool external_forces_ = false;   // apply_force() since ex_, ey_, ez_ were last cleared
    long resets_ = 0;
    long dropped_breaks_ = 0;
    bool finalized_ = false;
    bool uniform_cohesive_ = false;   // every link cohesive, all with the same parameters (finalize)
    bool portable_kernels_ = false;   // set_portable_kernels()
    bool use_avx2_ = false;           // finalize(): AVX2, 16 masses or more, portable_kernels_ off
};

}  // namespace ameoto
