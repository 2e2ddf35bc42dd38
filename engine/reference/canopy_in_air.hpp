// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The umbrella canopy in air, by the reference solver (engine/reference/air_solver.hpp): for the fast
// model's work on issue 19 to be held to. A flat Canopy's lattice (its node positions, links and
// anchors, masses and Rayleigh damping, read from CanopyGeometry and MembraneMaterial) becomes a
// ScreenStructure on the screen plane z = 0; each face of the plane under a panel belongs to the node
// Canopy::locate gives it (the nearest node of its panel); every other face is air (no baffle, no ribs'
// area, no shaft). The reference integrates the lattice itself (symplectic Euler at the air's step), not
// the Canopy class, so the two models share only the geometry and the material.
//
// Interface:
//   CanopyInAirSetup s;                    // geometry, material, dx, margin, duration, strike, listeners
//   s.listeners = {{0.0, 0.0, 0.3}};       // canopy coordinates (m): x, y from the shaft, z up
//   CanopyInAirResult r = run_canopy_in_air(s);   // throws std::invalid_argument (curved canopy, bad grid)
//   r.pressure[l][n]                       // Pa at listener l, sample n (time (n + 1) * r.sample_interval_s)
//   r.node_velocity[panel * r.nodes_per_panel + node][n]   // m/s along +z (the mean over the step)
//   std::vector<PanelMode> modes = panel_modes_in_air(s, 4);   // the struck panel's lowest modes: vacuum
//                                          // eigenfrequencies of the lattice and the air-loaded ones
//
// Given force_samples, the struck node's force is those samples instead (a drop's contact force).
// The strike: a raised-cosine force pulse of peak force_n and length pulse_s on one node, along +z, from
// t = 0. Node velocities are the structure's DOFs' mean velocity over each step (what the faces carry).
// A node whose Voronoi cell holds no face centre (dx too coarse) moves no air: nodes_without_faces counts
// them; keep dx below about half the lattice spacing.

#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/membrane.hpp"
#include "engine/reference/matrix_pencil.hpp"

namespace ameoto::reference {

struct CanopyInAirSetup {
    CanopyGeometry geometry{};                                  // flat only
    MembraneMaterial material = MembraneMaterial::nylon_canopy();
    double dx = 0.02;                                           // m
    double margin_m = 0.2;                                      // air beyond the rim, and above and below
    int pml_cells = 8;
    double duration_s = 0.05;
    int panel = 0, node = -1;                                   // struck node; -1: nearest the panel's centroid
    double force_n = 1.0, pulse_s = 2e-4;
    std::vector<Vec3> listeners;                                // canopy coordinates, m
    bool air = true;                                            // false: in vacuum (faces rigid, air silent)
    int record_every = 1;                                       // keep every n-th sample
    bool record_nodes = true;
    double z_margin_m = -1.0;                                   // air above and below; < 0: margin_m
    bool record_forces = false;                                 // keep each node's air force (below)
    std::vector<double> force_samples;                          // not empty: the struck node's force (N)
    double force_interval_s = 0.0;                              // at these intervals (linear between,
                                                                // 0 after), instead of the pulse
};

struct CanopyInAirResult {
    double time_step_s = 0.0, sample_interval_s = 0.0;
    int panels = 0, nodes_per_panel = 0, struck_node = -1, sub_steps = 1, nodes_without_faces = 0;
    long cells = 0, steps = 0;
    std::vector<std::vector<double>> pressure;                  // [listener][sample]
    std::vector<std::vector<double>> node_velocity;             // [panel * nodes + node][sample]
    std::vector<std::vector<double>> node_air_force;            // record_forces: the force the air puts
                                                                // on each node along +z (N), [node][sample]
};

CanopyInAirResult run_canopy_in_air(const CanopyInAirSetup& setup);

struct PanelMode {
    double vacuum_hz = 0.0;   // the lattice's own eigenfrequency (no air, no damping)
    double air_hz = 0.0;      // the peak of the struck panel's motion projected on that mode, in air
};
// The struck panel's `modes` lowest modes (record_every is set to 1 for it). The projection picks the
// mode out of the panel's own motion; the other panels ring with it through the air, so a mode of the
// whole canopy that the panels share (in phase, out of phase) is what is found.
std::vector<PanelMode> panel_modes_in_air(const CanopyInAirSetup& setup, int modes);

// The same estimator on a modal model of the canopy (the fast model's, engine/models/air_loading.hpp:
// modes of the whole canopy, node index panel * nodes + node, built for `canopy` with setup's geometry
// and material): the struck panel's velocity after the same pulse at the same node, by modal
// superposition (each mode's impulse response e^(-s t) (cos w_d t - (s / w_d) sin w_d t) for velocity,
// convolved with the pulse by a 40-point midpoint rule, sampled at 40 kHz for setup.duration_s),
// projected on the panel's vacuum modes and estimated alike. Hz, `modes` of them.
std::vector<double> modal_panel_modes(const CanopyInAirSetup& setup, const Canopy& canopy, const AirLoadedModes& air, int modes);

// What the two above estimate from: the struck panel's velocity projected on each of its vacuum mode
// shapes (unit-norm over the panel's nodes), m/s, sample n at time (n + 1) * sample_interval_s.
struct PanelProjections {
    double sample_interval_s = 0.0;
    std::vector<double> vacuum_hz;                  // [mode]
    std::vector<std::vector<double>> velocity;      // [mode][sample]
};
PanelProjections panel_projections_in_air(const CanopyInAirSetup& setup, int modes);   // the reference
PanelProjections modal_panel_projections(const CanopyInAirSetup& setup, const Canopy& canopy, const AirLoadedModes& air, int modes);

// The estimator both models share: the frequency of the largest peak of the projection's first record_s
// (Hann window, band 0.2 to 1.05 of the vacuum frequency), Hz. panel_modes_in_air and modal_panel_modes
// use kPeakRecordS, the window of the cached figures, whatever setup.duration_s is (a longer record serves
// panel_mode_components). In air a panel mode is no single mode: the air couples the eight panels into
// canopy modes (the panels' Fourier copies, 2-8 % apart) and mixes the panel's own shapes, so the peak is
// a blend of the copies that the window cannot separate (docs/canopy-air.md).
inline constexpr double kPeakRecordS = 0.1;
double panel_mode_frequency(const std::vector<double>& projection, double dt, double vacuum_hz, double record_s);

// The canopy modes in a projection: damped sinusoids fitted from the end of the pulse by the matrix
// pencil (matrix_pencil.hpp; band 0.2 to 1.05 of the vacuum frequency, singular values above 1e-4 of the
// largest), sorted by frequency. It separates the copies given 0.4 s of record (in 0.1 s it cannot:
// they lie 8-20 Hz apart, about 1 / 0.1 s); record_energy gives each one's share.
std::vector<DampedSinusoid> panel_mode_components(const std::vector<double>& projection, double dt, double vacuum_hz, double pulse_s);

}  // namespace ameoto::reference
