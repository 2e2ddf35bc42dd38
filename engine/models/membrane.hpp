// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A membrane under tension as a triangular mass-spring lattice (transverse displacement), and the
// materials it can be made of.
//
// Interface:
//   MembraneMaterial nylon = MembraneMaterial::nylon_canopy();         // presets: "nylon", "seed-nylon",
//   auto vinyl = membrane_material("vinyl");                           // "vinyl" (alias "pvc"); nullopt
//                                                                      // for an unknown name
//   MembraneMaterial c = MembraneMaterial::custom("tin", s, T, alpha, beta);
//   MaterialCheck v = validate_membrane_material(c);                   // ranges: v.ok, v.reason
//   MaterialCheck k = check_membrane_material(polygon, 50, c, T, NetworkOptions{...});
//                                    // ranges, then the stability bound for the chosen integrator and
//                                    // policy: refused with "omega_max T = ... exceeds 2 ..." or run
//                                    // with k.stability.sub_steps; never throws
//   Membrane m = build_membrane(polygon, target_masses, nylon, time_step_s);
//   Membrane s = build_membrane(polygon, 50, MembraneMaterial::seed_nylon(), T,
//                               NetworkOptions{...});   // integrator, stability policy, guard; throws
//                                                       // StabilityError when refused
//   m.network      // the TransverseNetwork to step
//   m.lattice      // geometry: node positions, links, anchors
//
// From continuum to lattice: the membrane equation s u_tt = T lap(u) - damping, with areal density
// s (kg/m^2) and tension T (N/m). A node of the triangular lattice of spacing h stands for the area
// A = (sqrt 3 / 2) h^2, so its mass is s A. The six-neighbour Laplacian on that lattice is
// lap(u) ~ 2 / (3 h^2) sum_j (u_j - u_i), so the force on a node is T A lap(u) = (T / sqrt 3) sum_j
// (u_j - u_i): every link is a spring of stiffness k = T / sqrt 3, independent of h. Links to the fixed
// ribs are the same springs to fixed points.
// Damping is Rayleigh (proportional) damping C = alpha M + beta K: alpha as a damper from each mass to
// the ground, beta k on every link. A mode of angular frequency w then decays at (alpha + beta w^2)/2
// per second (loss factor eta(w) = alpha / w + beta w), which keeps the modal model
// (core/integrators/modal.hpp) exact for the same body.
// Given directly (the seed's figures): link_stiffness > 0 replaces T / sqrt 3, total_mass > 0 replaces
// s A per node by total_mass / nodes, link_damping > 0 replaces beta k on every link and anchor link
// (still proportional: C = (z / k) K + alpha M).
//
// Presets (docs/canopy.md "Materials" has the table with the measured modes of the default panel):
//   nylon       s = 0.06 kg/m^2, T = 1000 N/m, alpha 20 /s, beta 2e-6 s (eta 0.013 .. 0.033, 100 Hz - 2 kHz)
//   vinyl       s = 0.20 kg/m^2, T = 200 N/m, alpha 60 /s, beta 1.6e-5 s (eta 0.06 .. 0.2, 50 Hz - 2 kHz)
//   seed-nylon  0.12 kg per panel, links 1.2e9 N/m, dampers 0.231 N s/m (seed section 5.1.2)
// Validation ranges (validate_membrane_material; each refusal names the value, the range and why):
//   areal density 1e-3 .. 100 kg/m^2, tension 0.1 .. 1e10 N/m, alpha 0 .. 1e4 1/s, beta 0 .. 1e-3 s,
//   link stiffness 0 (unused) or up to 1e10 N/m, total mass 0 (unused) or 1e-6 .. 100 kg, link damping
//   0 (unused) or up to 1e3 N s/m.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/transverse_network.hpp"
#include "engine/core/triangular_lattice.hpp"

namespace ameoto {

struct MembraneMaterial {
    std::string name;
    double areal_density = 0.06;   // kg/m^2
    double tension = 1000.0;       // N/m
    double mass_damping = 20.0;    // alpha, 1/s
    double stiffness_damping = 2e-6;   // beta, s
    double link_stiffness = 0.0;   // N/m per link; > 0 overrides tension / sqrt 3
    double total_mass = 0.0;       // kg per membrane; > 0 overrides areal_density * node area
    double link_damping = 0.0;     // N s/m per link; > 0 overrides stiffness_damping * k

    double wave_speed() const;     // c = sqrt(T / s), m/s
    bool operator==(const MembraneMaterial&) const = default;

    // Nylon umbrella fabric: 60 g/m^2 (typical canopy taffeta is 50-70), tensioned to 1 kN/m: a taut
    // canopy, above the 120-640 N/m that the estimates in docs/canopy.md ("Materials") suggest; the
    // ~50-mass panel's modes then span 217 Hz to 1.1 kHz. Loss factor 0.013-0.033 (a light, lightly
    // damped fabric).
    static MembraneMaterial nylon_canopy();

    // The seed's umbrella panel (physics.md section 1): 0.12 kg of nylon per panel, links of 1.2e9 N/m
    // ("tension 0.12e10" read as link stiffness) with 0.231 N s/m dampers, no ground damping. Its
    // areal density (0.12 kg over the default 8 x 0.5 m canopy's panel, 0.0884 m^2) and tension
    // (sqrt 3 k) are the equivalent continuum, for wave_speed() and the renderer's pressure gain. Stiff:
    // omega_max T ~ 50 at 48 kHz on a 50-mass panel, so the explicit scheme needs 27 sub-steps
    // (physics.md section 3 last bullet; tests/engine/models/membrane_test.cpp, "seed umbrella"), and
    // every mode of the panel is ultrasonic (65 to 332 kHz).
    static MembraneMaterial seed_nylon();

    // A clear PVC (vinyl) umbrella, the seed's future work (section 6): 0.15 mm of plasticised PVC at
    // about 1330 kg/m^3 (flexible PVC 1.1-1.45 g/cm^3) is 0.20 kg/m^2; tension 200 N/m (a film of about
    // 16 MPa strength, 2.4 kN/m at 0.15 mm, prestressed to under 10 % of it); PVC is a lossy
    // viscoelastic polymer: Rayleigh damping for a loss factor of about 0.1 (0.06-0.2) over 50 Hz-2 kHz.
    static MembraneMaterial vinyl();

    // Any density, tension and Rayleigh damping (OSC's custom surface material). Not validated here:
    // call validate_membrane_material or check_membrane_material before building with it.
    static MembraneMaterial custom(std::string name, double areal_density, double tension, double alpha,
                                   double beta);
};

// The presets by name ("nylon", "seed-nylon", "vinyl"; "pvc" is vinyl); nullopt for any other name.
std::optional<MembraneMaterial> membrane_material(std::string_view name);
const std::vector<std::string>& membrane_material_names();

struct MaterialCheck {
    bool ok = true;
    std::string reason;            // why not (empty when ok); for stability refusals the bound's message
    StabilityReport stability;     // filled by check_membrane_material when the ranges passed
};

MaterialCheck validate_membrane_material(const MembraneMaterial& material);
MaterialCheck check_membrane_material(const std::vector<PolygonEdge>& polygon, int target_masses,
                                      const MembraneMaterial& material, double time_step_s,
                                      const NetworkOptions& options = NetworkOptions{});

struct Membrane {
    TriangularLattice lattice;
    TransverseNetwork network;
    MembraneMaterial material;
};

Membrane build_membrane(const std::vector<PolygonEdge>& polygon, int target_masses,
                        const MembraneMaterial& material, double time_step_s,
                        const NetworkOptions& options = NetworkOptions{});

}  // namespace ameoto
