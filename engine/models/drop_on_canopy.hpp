// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The seed's whole scene for one (or a few) drops: lattice drops (drop_pool.hpp) falling on the umbrella
// canopy (canopy.hpp), colliding with its membrane masses (membrane_collision.hpp), heard through the
// far-field Rayleigh sum or the seed's single-mass pickup (radiation.hpp). What `ameoto render drop`
// renders offline, and a test bench for the physics end to end.
//
// Interface:
//   DropOnCanopyConfig config;                       // sample rate, material, liquid, geometry, output...
//   config.material = MembraneMaterial::vinyl(); config.liquid = liquids::milk();
//   config.output = SceneOutput::far_field; config.channels = 2;   // or SceneOutput::mass_pickup
//   config.listener = ListenerStyle::panned;         // stereo over speakers (ears: binaural spacing)
//   DropOnCanopy scene(config);                      // allocates everything; throws std::invalid_argument
//                                                    // (bad config, material, liquid: with the reason) or
//                                                    // StabilityError (a material refused)
//   Canopy proto = DropOnCanopy::fresh_canopy(config);   // the canopy that constructor builds, alone
//   DropOnCanopy run(config, proto);                 // the same scene, bit for bit, with a copy of proto
//                                                    // for its canopy instead of building one (most of
//                                                    // the constructor's cost): many short runs of one
//                                                    // configuration (impact_templates.hpp) build it once.
//                                                    // proto must come from fresh_canopy(config) (or an
//                                                    // equal config) and never be stepped; its geometry
//                                                    // is checked (std::invalid_argument)
//   DropOnCanopy next(config, proto, run);           // the same again, its far field's push filters
//                                                    // shared with run's where designed alike
//                                                    // (DipoleRadiation's sibling: same bits, and about
//                                                    // 30 ms less a listening point in air)
//   ---- audio-safe from here: no allocation, no locks ----
//   bool ok = scene.drop(5e-3, 0.0, 0.2, 0.0);       // D (m), speed (m/s, 0: terminal), plan point (m);
//                                                    // false: off the canopy, bad size or pool full
//   scene.process(frames, outputs);                  // outputs[channel][frame], float
//   scene.process_frame(frame);                      // one sample: frame[channel]
//   scene.surface().apply_force(hit, newtons);       // an outside force on the canopy (held one step:
//                                                    // the renderer's impulse-model rain)
//   scene.full()                                     // no free drop slot
//   DropOnCanopyStats s = scene.stats();             // pieces, masses, breakups, collisions
//   ---- off the audio thread ----
//   std::vector<SceneMass> m = scene.snapshot();     // every drop mass: position, drop, piece (plots)
//   scene.canopy(), scene.pool()                     // the parts, read-only
//
// Order within one sample (membrane_collision.hpp): collide (forces held for the next step), step the
// canopy, step the drops, then read the sound from the canopy just stepped. The canopy's runtime
// guard (Canopy::reset_unstable) runs every guard_interval samples (256), or when the caller calls
// guard(). Collisions are collide_drops' exactly (bit for bit, tested), but masses that cannot reach the
// membrane this step are not looked up: off the rim's circle, above the membrane's highest node (when
// collide() has read the membrane's extremes: after an impact, or while it is far displaced), beyond a
// 5 cm band around the rest cap otherwise, or below it by more than the band plus their own travel
// (drop_on_canopy_collide.cpp, collide(), gives the argument); a whole drop whose lowest mass is above is passed
// over at once (DropPool::lowest_z).
//
// Coarse steps (drop_pool.hpp): collide() sets each drop's floor each sample (with settling, from that
// drop's own lowest mass: the membrane's highest point plus 2 mm and the collider's skin while the drop
// hangs in the band over the membrane, the band's top otherwise; "Settling" below; without it one floor
// for the pool, the membrane's highest point when read that sample), so a splash wholly in the air
// above it steps up to coarse_steps samples at once. Nothing can touch it meanwhile: the
// sound is what stepping every sample gives, bit for bit, until a piece comes down again (tested).
//
// Impact (config.impact): wet, the default, stops each drop mass as its parcel of liquid arrives and
// holds it on the membrane (a real drop's impulse m V on a rigid target, Gordillo et al. 2018:
// wet_impact.hpp, docs/impacts.md); seed, the seed's exchange with restitution e (1: elastic, returning
// the momentum: twice a real drop's impulse). Wet masses touch up to their reach (their parcel's
// radius, at most 1 mm) above the membrane, so the broad phase below adds that reach to its bounds.
//
// Settling (config.settle, the default): every 32 of a drop's own samples each piece of a
// drop whose masses are all done is parked (DropPool, "Parking": taken out of the motion, its mass
// kept), and a drop whose pieces are all parked retires. A mass is done (settle_predicate()) when it can
// no longer be heard: gone past the rim (outside the rim's circle by 1 cm, moving outwards: only
// gravity and drag act on a piece in flight, and drag only slows it, so it never comes back over the
// cap);
// under the cap by more than the 5 cm band the membrane never reaches, moving down; or at rest on it
// (within its reach plus 1 mm over the rest cap and 3 mm under it, moving along the normal slower than
// rest_speed_m_per_s, 5 cm/s). Such liquid only loads the membrane with its weight and its mass (a
// 5 mm drop's 65 mg against a panel's 5.3 g); leaving it in the motion cost a drop's whole lattice
// every sample, since a piece at rest holds the drop's coarse steps down (the splash's flying pieces
// could not be stepped coarsely while any piece lay on the membrane). What it changes in the sound is
// bounded by a test (drop_on_canopy_test: band levels of a render with and without, docs/drop.md).
// Each drop's coarse steps take their floor from its own lowest mass and the membrane (set_drop_floors in
// drop_on_canopy_collide.cpp), and its checks come every 32 of its own samples: a drop's samples depend on its
// own history and the canopy, never on when another drop was spawned (drop_settle_independence_test).
// settle = false is the model before it (ameoto bench drop and bench scene time both).
//
// Placement: drop() puts the drop's lowest mass gap_m (0.5 mm) above the rest surface at (x, y)
// (DropPool::underside; wet: its parcel's underside, the mass's reach lower), moving straight down at `speed`, so it reaches the membrane within a few
// samples (a 5 mm drop at 9.1 m/s covers 0.19 mm per sample at 48 kHz); with gap_m = 0 it strikes at
// once. acoustic_delay_samples(x, y) is the delay from that point of the cap to the nearest listening
// point: when the impact is first heard. Speed 0 means the drop's arrival speed
// (Gunn & Kinzer's terminal speed for its density, drop.hpp).
//
// In air (config.air): the canopy runs its air-loaded modes (Canopy::set_air; built with the canopy,
// about half a second for the default one) and the far field is the unbaffled dipole sum
// (dipole_radiation.hpp) at the same listening points; the collisions, the pickup and the broad phase
// read the modes through the canopy as they read the lattice. The network options are then unused.
// Output: far field: each channel is the pressure at its listening point divided by full_scale_pa, so
// 1.0 is full_scale_pa pascals. The head is listener_below_m under the shaft, facing +x. One channel:
// ListenerLayout::mono. Two channels: ListenerStyle::ears (two points 0.18 m apart: headphones) or
// ::panned (one point; each panel's pressure panned by its azimuth, panning.hpp: loudspeakers). Three
// to 16 channels: panned over a ring of speakers. latency_samples() is the shortest acoustic delay,
// node to listening point: an impact is heard that many samples after it happens. Mass pickup: the displacement of the node under
// pickup_x/y over its default full scale (radiation.hpp), the same signal on every channel.
//
// Conservation: masses are never created or removed (drop_pool.hpp). stats() sums, over the active
// drops, the masses and their kilograms now and as they were at spawn, in the same order, so the
// totals are equal exactly while no drop has retired (a drop retires when all its masses fall below
// retire_below_m, or after max_lifetime_s).

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/models/air_canopy.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/dipole_radiation.hpp"
#include "engine/models/drop_pool.hpp"
#include "engine/models/liquid.hpp"
#include "engine/models/membrane.hpp"
#include "engine/models/membrane_collision.hpp"
#include "engine/models/radiation.hpp"

namespace ameoto {

enum class SceneOutput { far_field, mass_pickup };
// ambix: one listening point; each panel's pressure encoded by the direction of its centre from the
// head (ACN/SN3D, ambisonics.hpp) on 4, 9 or 16 channels (orders 1 to 3).
enum class ListenerStyle { ears, panned, ambix };

struct DropOnCanopyConfig {
    double sample_rate = 48000.0;                  // Hz, 8000..384000
    MembraneMaterial material = MembraneMaterial::nylon_canopy();
    Liquid liquid = liquids::water();
    CanopyGeometry geometry{};
    SceneOutput output = SceneOutput::far_field;
    int channels = 1;                              // 1..16 (the pickup is the same on every channel)
    ListenerStyle listener = ListenerStyle::ears;  // two channels: ears or panned (3+: panned, or ambix
                                                   // on 4, 9 or 16)
    ImpactModel impact = ImpactModel::wet;         // how a drop mass meets the membrane (wet_impact.hpp):
                                                   // wet (a real drop's impulse m V, spreading) or seed
                                                   // (the seed's exchange, restitution below)
    double restitution = 1.0;                      // 0..1, the seed exchange's e (1: elastic, the seed's)
    int capacity = 8;                              // drops at once
    double max_diameter = 8e-3;                    // m, the largest drop drop() accepts
    double gap_m = 0.5e-3;                         // m, between the drop and the surface at spawn
    double listener_below_m = 0.3;                 // m, the listener's head under the shaft
    double full_scale_pa = 100.0;                  // Pa for output 1.0 (far field; 134 dB SPL)
    double pickup_x = 0.2, pickup_y = 0.05;        // m, the pickup's plan point (mass pickup)
    double retire_below_m = -1.0;                  // m: a drop whose masses are all below retires
    double max_lifetime_s = 30.0;                  // s (0: never)
    int coarse_steps = 4;                          // 1..64: samples a drop wholly over the band may take
                                                   // as one (drop_pool.hpp, "Coarse steps"; 1: never)
    bool settle = true;                            // park liquid that is done (above, "Settling"); false:
                                                   // every mass is stepped until its drop retires (the model before)
    double rest_speed_m_per_s = 0.05;              // m/s: slower along the normal, a mass in touch is at rest
    int guard_interval = 256;                      // samples between runs of the canopy's guard (0: only
                                                   // when the caller calls guard())
    NetworkOptions network{};                      // the panels' integrator (core/method_choice.hpp picks
                                                   // it from an accuracy budget)
    bool air = false;                              // true: the canopy in air (its air-loaded modes,
                                                   // air_canopy.hpp, heard as dipoles, dipole_radiation.hpp;
                                                   // flat or curved); false: the lattice in vacuum under the
                                                   // baffled Rayleigh sum (network above), the seed's model
    AirCanopyOptions air_options{};                // in air: the air, the added mass's sampling, the cutoff
    bool air_push = true;                          // in air, heard in the far field: each contact's push
                                                   // above the modes through compressible air (air_push.hpp);
                                                   // false: the modes' taps alone (the model before it)
    bool operator==(const DropOnCanopyConfig&) const = default;
};

struct DropOnCanopyStats {
    int active_drops = 0;
    int pieces = 0;                 // pieces of the active drops, summed (one per whole drop)
    int largest_pieces = 0;         // the most pieces any active drop has
    int masses = 0;                 // masses of the active drops now
    int masses_at_spawn = 0;        // and when they were spawned (equal: conservation)
    double mass_kg = 0.0;           // kilograms of the active drops now
    double mass_at_spawn_kg = 0.0;  // and at spawn, summed in the same order
    long spawned = 0, retired = 0;
    long breakups = 0;              // pieces gained (DropPoolStats::breakups)
    long link_breaks = 0;
    std::uint64_t collisions = 0;   // drop mass / membrane mass collisions so far
    std::uint64_t drops_passed_over = 0;   // drops the collision broad phase skipped whole (per step)
    std::uint64_t drops_passed_over_in_band = 0;   // of them, with their lowest mass in the band, skipped
                                                   // by the membrane's displacement read that step
    long canopy_resets = 0;         // panels reset by the guard (never expected)
    std::uint64_t frames = 0;       // samples processed
};

struct SceneMass {
    Vec3 position;                  // m, canopy coordinates
    Vec3 velocity;                  // m/s
    int drop = 0;                   // pool slot
    std::uint64_t serial = 0;       // spawn number of its drop (1, 2, ...)
    int piece = 0;                  // its piece within the drop
    bool parked = false;            // settled (config.settle): position is where it was parked
};

// The collider's options for a configuration: CollisionOptions::seed(restitution) for ImpactModel::seed,
// CollisionOptions::wet(liquid density) for wet.
CollisionOptions collision_options(const DropOnCanopyConfig& config);

// Settling's test of one mass (position, velocity in canopy coordinates): done, as above. `touch` is
// how far above the rest cap a mass is touched (the collider's reach cap; 0 for the seed).
std::function<bool(Vec3, Vec3)> settle_predicate(const DropOnCanopyConfig& config, double touch_m);

class DropOnCanopy {
public:
    explicit DropOnCanopy(const DropOnCanopyConfig& config);
    DropOnCanopy(const DropOnCanopyConfig& config, const Canopy& prototype);
    DropOnCanopy(const DropOnCanopyConfig& config, const Canopy& prototype, const DropOnCanopy& sibling);
    static Canopy fresh_canopy(const DropOnCanopyConfig& config);   // checks config first, as the constructor

    bool drop(double diameter_m, double speed_m_per_s, double x_m, double y_m);
    void process(int frames, float* const* outputs);
    void process_frame(float* frame);
    Canopy& surface() { return canopy_; }
    bool full() const { return static_cast<int>(pool_.active().size()) >= pool_.capacity(); }
    int latency_samples() const { return latency_samples_; }
    int guard();                                   // the canopy's guard now: panels reset (counted in stats)
    // The listener's head turned by `head` (ambisonics.hpp's head_rotation, row-major) within the body
    // that holds the umbrella: on the panned formats (2+ channels, ListenerStyle::panned, in vacuum or air) each
    // panel is re-panned by the azimuth its centre is heard from, H^T d (the full rotation, so a pitch or
    // roll moves an overhead panel's azimuth), the gains gliding over glide_frames samples. Audio thread,
    // no allocation; in air the dipole model's taps are re-mixed from each panel's own. Returns false
    // where it has nothing to turn: mono, ears (the two ear points are built into the radiator's taps),
    // ambix (the renderer rotates the bus). drop_on_canopy_turn.cpp.
    bool turn_head(const std::array<double, 9>& head, int glide_frames);
    // N: the sum of the collision forces the last sample put on drop masses (the membrane took the
    // opposite); what impact_templates.hpp records.
    Vec3 contact_force() const { return contact_force_; }
    double acoustic_delay_samples(double x_m, double y_m) const;
    DropOnCanopyStats stats() const;
    std::vector<SceneMass> snapshot() const;

    const DropOnCanopyConfig& config() const { return config_; }
    const Canopy& canopy() const { return canopy_; }
    const DropPool& pool() const { return pool_; }
    const DipoleRadiation& dipole() const { return dipole_; }   // in air: its taps (turn_head re-mixes them)
    int channels() const { return config_.channels; }
    double time_step() const { return dt_; }

private:
    static const DropOnCanopyConfig& checked(const DropOnCanopyConfig& config);
    struct Built {};   // the delegated constructor's tag: config already checked, canopy given
    DropOnCanopy(Built, const DropOnCanopyConfig& config, Canopy&& canopy, const DropOnCanopy* sibling = nullptr);
    void collide();
    void prepare_turn();   // constructor: turn_head's buffers (drop_on_canopy_turn.cpp)
    void set_drop_floors(bool have_u, double above, double skin, double per_normal);
    DropOnCanopyConfig config_;
    double dt_;
    Canopy canopy_;
    DropPool pool_;
    MembraneCollider collider_;
    FarFieldRadiation far_field_;
    DipoleRadiation dipole_;      // in air (config_.air)
    MassPickup pickup_;
    int liquid_ = 0;
    std::vector<double> panel_forces_, pressures_;
    std::vector<Vec3> panel_directions_;  // turn_head: each panel's centre from the head (panned formats)
    std::vector<double> turn_gains_;      // turn_head's gains [channel * panels + panel]
    std::vector<int> spawn_masses_;       // per slot
    std::vector<double> spawn_mass_kg_;   // per slot
    double top_ = 0.0, bottom_ = 0.0, reach_ = 0.05;   // m: the band where masses can collide
    double touch_ = 0.0;          // m: how far above a node a mass may be touched (wet: the reach cap)
    long canopy_resets_ = 0;
    std::uint64_t frames_ = 0;
    int latency_samples_ = 0;
    std::vector<Vec3> listener_points_;
    Vec3 contact_force_{};
    double rim_normal_z_ = 1.0;   // n_z of the rest cap at the rim: the smallest inside it
    int near_masses_ = 0;         // masses in the band last step   } when collide() reads the
    int unread_steps_ = 0;        // steps since it read u           } membrane's displacement
    bool displaced_ = false;      // |u| beyond a quarter of the band at that reading
    std::uint64_t drops_passed_over_in_band_ = 0;
    std::uint64_t drops_passed_over_ = 0;   // stats()
    std::vector<int> scan_;       // collide(): an awake drop's masses to look at (collision_scan.hpp)
    std::vector<double> node_velocities_;   // collide(): the membrane's du/dt (settling's coarse floor)
};

}  // namespace ameoto
