#pragma once
// A membrane under tension as a triangular mass-spring lattice (transverse displacement).
//
// Interface:
//   MembraneMaterial nylon = MembraneMaterial::nylon_canopy();
//   Membrane m = build_membrane(polygon, target_masses, nylon, time_step_s);
//   Membrane s = build_membrane(polygon, 50, MembraneMaterial::seed_nylon(), T,
//                               NetworkOptions{...});   // integrator, stability policy, guard
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
// per second, which keeps the modal model (core/integrators/modal.hpp) exact for the same body.
// Given directly (the seed's figures): link_stiffness > 0 replaces T / sqrt 3, total_mass > 0 replaces
// s A per node by total_mass / nodes, link_damping > 0 replaces beta k on every link and anchor link
// (still proportional: C = (z / k) K + alpha M).

#include <string>
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

    // Nylon umbrella fabric: 60 g/m^2 (typical canopy taffeta is 50-70), tensioned to 1 kN/m so that
    // the ~50-mass panel's modes span the few hundred Hz to ~2 kHz band of a taut umbrella. See
    // docs/engine.md for the measured modes.
    static MembraneMaterial nylon_canopy();

    // The seed's umbrella panel (physics.md section 1): 0.12 kg of nylon per panel, links of 1.2e9 N/m
    // ("tension 0.12e10" read as link stiffness) with 0.231 N s/m dampers, no ground damping. Its
    // areal density (0.12 kg over the default 8 x 0.5 m canopy's panel, 0.0884 m^2) and tension
    // (sqrt 3 k) are the equivalent continuum, for wave_speed() and the renderer's pressure gain. Stiff:
    // omega_max T ~ 50 at 48 kHz on a 50-mass panel, so the explicit scheme needs ~30 sub-steps
    // (physics.md section 3 last bullet; tests/engine/models/membrane_test.cpp, "seed umbrella").
    static MembraneMaterial seed_nylon();
};

struct Membrane {
    TriangularLattice lattice;
    TransverseNetwork network;
    MembraneMaterial material;
};

Membrane build_membrane(const std::vector<PolygonEdge>& polygon, int target_masses,
                        const MembraneMaterial& material, double time_step_s,
                        const NetworkOptions& options = NetworkOptions{});

}  // namespace ameoto
