// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// How a drop mass meets what it strikes: the wet impact (default) or the seed's elastic exchange, and a
// measurement of a whole lattice drop on a rigid plane (docs/impacts.md).
//
// Interface:
//   ImpactModel::wet, ImpactModel::seed; impact_model_name(m); find_impact_model("wet")   // names
//   ContactLaw law{ImpactModel::wet, 1.0, 1e-3, 998.0, 1e-3};   // model, e (seed), skin, rho, reach cap
//   double r = law.reach(m1);                   // m: how far above the surface a mass of m1 kg touches
//   ContactImpulse c = contact_impulse(law, m1, m2, h, v1, v2, T);   // one mass, one step: audio-safe,
//                                               // no allocation (MembraneCollider and the rigid plane
//                                               // below both call it; m2 may be +infinity: rigid)
//   ---- off the audio thread (allocates) ----
//   RigidImpact r = measure_rigid_impact(RigidImpactSpec{.diameter_m = 2e-3, .sample_rate = 48000});
//   r.force[n], r.impulse_n_s, r.peak_n, r.length_s, r.energy (where the energy went)
//
// The seed (section 4.3): a mass whose centre has reached the surface while closing exchanges momentum
// with the node under it with restitution e (membrane_collision.hpp): e = 1, the seed's, returns the
// momentum, so a drop gives twice the impulse m V a real one gives (acoustics.md section 3).
//
// Wet (the default). A real drop does not bounce: it spreads, and its impulse on a rigid target is m V,
// with a force that rises like t^(1/2), peaks near 0.8 rho V^2 D^2 and lasts of order D / V (Gordillo,
// Sun & Cheng, J. Fluid Mech. 840:190, 2018; Soto et al., Phys. Rev. Fluids 2014). The liquid that
// reaches the wall is stopped and turned sideways while the liquid above still arrives at V: the
// stopping front moves up through the drop at about the impact speed. Each lattice mass stands for a
// parcel of liquid of diameter l = (6 m / (pi rho))^(1/3) (its share of the drop's volume), and is
// stopped the same way, over the time its own parcel takes to arrive, tau = l / w0 (w0 its closing speed
// at first touch), with the pulse shape of the engine's impact law (impact_force.hpp):
//   f(t) = (m w0 / tau) phi(s),  phi(s) = (15/4) s^(1/2) (1 - s),  s = t / tau in [0, 1],
// whose integral is m w0 (Phi(s) = 5/2 s^(3/2) - 3/2 s^(5/2)): the parcel's normal momentum, no rebound.
// Under it the parcel's closing speed is w = w0 b(s), b = 1 - Phi, and the depth its centre has gone
// since its parcel touched is delta = l A(s), A(s) = s - s^(5/2) + (3/7) s^(7/2), at most (3/7) l. So
// the phase s follows from the depth alone, s = A^-1(delta / l), and w0 = w / b(s) from the speed: the
// law is a force of the state (depth, closing speed), F = (m w^2 / l) phi(s) / b(s)^2, and needs no
// memory of the impact, however the lattice pushes the mass meanwhile. A mass touches when its centre
// is within reach r = l / 2 of the surface (its parcel's underside; capped at max_reach_m) and is
// held at depth (3/7) l: beyond it, or once the pulse is over, it meets the surface with e = 0 (closing
// speed removed, a liquid at rest on the surface). Tangential motion is free (no friction): the
// lattice spreads and throws its splash sideways, and links break as before (drop.hpp).
// Discrete step T: the impulse is the pulse's exact integral from s to s + T w0 / l (as
// impact_force.hpp delivers its law sample by sample), so it never exceeds the parcel's momentum and
// never pulls; and at most mu w (mu = m1 m2 / (m1 + m2)): the pair never separates because of it. A
// single-mass drop (D < 1.15 mm) is one parcel of the drop's size: its pulse is the impact law's
// itself (peak 0.755 rho V^2 D^2, length D / V); a lattice drop's is the sum of its parcels' as its
// layers arrive (measured: docs/impacts.md).
// Detection (both models): h is the mass centre's height above the surface, v1, v2 the mass's and the
// surface's normal speeds; closing = v1 - v2 < 0 is required; a mass deeper than its reach's hold
// depth plus T |closing| + skin is under the surface (the swept test of membrane_collision.hpp) and
// is ignored. Seed: reach 0, hold depth 0 (the seed's test exactly).

#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/models/liquid.hpp"

namespace ameoto {

enum class ImpactModel : std::uint8_t { wet, seed };

const char* impact_model_name(ImpactModel model);               // "wet", "seed"
std::optional<ImpactModel> find_impact_model(std::string_view name);

struct ContactLaw {
    ImpactModel model = ImpactModel::wet;
    double restitution = 1.0;                        // e, the seed's exchange (model seed only)
    double skin_m = 1e-3;                            // contact depth kept beyond the swept depth
    double liquid_density = constants::water_density;   // kg/m^3: a mass's parcel size (wet)
    double max_reach_m = 1e-3;                       // m: the reach's cap (a bound for broad phases)

    // m: the mass's parcel diameter l (wet), 0 for the seed.
    double parcel(double mass_kg) const;
    // m: r = l / 2, capped at max_reach_m (wet); 0 for the seed.
    double reach(double mass_kg) const;
};

struct ContactImpulse {
    bool contact = false;
    double impulse = 0.0;      // N s on the mass along the normal (the surface takes -impulse)
    double dissipated = 0.0;   // J: the pair's kinetic energy the exchange removes, (1/2) mu (w^2 - w'^2)
};

// One mass of m1 kg whose centre is h m above the surface (negative: below), normal speeds v1 (mass)
// and v2 (surface), against a surface mass m2 (+infinity: rigid), for a step of T s.
ContactImpulse contact_impulse(const ContactLaw& law, double m1, double m2, double h, double v1, double v2,
                               double time_step_s);

// The same with the mass's parcel diameter given, parcel_m = law.parcel(m1) (a caller that meets many
// masses of one size computes the cube root once: MembraneCollider). The same result to the bit.
ContactImpulse contact_impulse_of_parcel(const ContactLaw& law, double parcel_m, double m1, double m2, double h, double v1,
                                         double v2, double time_step_s);

// The wet pulse's phase s (0..1) at a depth of `depth_over_parcel` parcel diameters (A^-1 above); 1 at
// and beyond 3/7. Exposed for tests.
double wet_phase(double depth_over_parcel);

struct RigidImpactSpec {
    double diameter_m = 2e-3;
    double speed_m_per_s = 0.0;           // 0: terminal speed (Gunn & Kinzer, drop.hpp's arrival_speed)
    double sample_rate = 48000.0;         // Hz
    ContactLaw law{};                     // liquid_density is taken from `liquid`
    Liquid liquid = liquids::water();
    double window_over_tau = 4.0;         // the pulse is measured over this many D / V from first contact
    double seconds = 0.0;                 // s simulated (0: the window); the energy table is at the end
};

struct ImpactEnergy {                     // J, from the drop's release to the end of the run
    double initial_kinetic = 0.0;         // (1/2) m V^2 at release
    double gravity_work = 0.0;            // m g (fall of the centre of mass) since release
    double kinetic = 0.0;                 // at the end: the pieces' motion (spreading, splash)
    double kinetic_flying = 0.0;          // of it, in pieces with no mass in contact at the end
    double elastic = 0.0;                 // stored in links (springs and cores) at the end
    double collision = 0.0;               // removed by the contact (each step's (1/2) mu (w^2 - w'^2))
    double viscous = 0.0;                 // the links' dampers (the liquid's viscosity, Lamb's rate)
    double drag = 0.0;                    // air drag
    double broken = 0.0;                  // held by links when they broke (k (L - l0)^2 / 2 each)
    double residual() const {             // what the sum misses (the integrator's own error)
        return initial_kinetic + gravity_work -
               (kinetic + elastic + collision + viscous + drag + broken);
    }
};

struct RigidImpact {
    double diameter_m = 0.0, speed_m_per_s = 0.0, mass_kg = 0.0, sample_rate = 0.0;
    int masses = 0;
    std::vector<double> force;            // N on the plane (pushing down: positive), per sample
    int first_contact = -1;               // sample of the first non-zero force
    double impulse_n_s = 0.0;             // sum of force T over the window
    double peak_n = 0.0;                  // largest per-sample force in the window
    double peak_time_s = 0.0;             // from the first contact's sample start
    double length_s = 0.0;                // span in which the middle 90 % of the impulse is delivered
    int pieces = 1;                       // at the end
    long link_breaks = 0;
    ImpactEnergy energy;

    double momentum() const { return mass_kg * speed_m_per_s; }   // m V
    double gordillo_peak(double density) const {                   // 0.8 rho V^2 D^2
        return 0.8 * density * speed_m_per_s * speed_m_per_s * diameter_m * diameter_m;
    }
    double tau() const { return diameter_m / speed_m_per_s; }      // D / V
};

// The lattice drop (drop.hpp, in a DropPool as the scene runs it) released with its lowest parcel just
// touching the plane z = 0 at speed V straight down, under gravity and air drag, each of its masses
// meeting the plane by contact_impulse with m2 = +infinity. Throws std::invalid_argument for a bad spec.
RigidImpact measure_rigid_impact(const RigidImpactSpec& spec);

}  // namespace ameoto
