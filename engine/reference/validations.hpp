// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The air reference's validations (issue 19, part 1), each a function of its grid so that the tests run
// coarse grids and `ameoto reference` fine ones. docs/air-reference.md has the figures.
//
// Interface:
//   PistonResult r = baffled_piston({.cells_per_radius = 8});    // on-axis pressure against Kinsler's
//   DiscResult d = rigid_disc({.cells_per_radius = 6});          // Lamb's added mass, the dipole's far field
//   TimpaniResult t = timpani({.cells_per_radius = 12});         // Christian et al.'s head in free air
//   ReflectionResult b = layer_reflection({.pml_cells = 10});    // what the absorbing layer sends back
//
// Radii are staircased: a disc is the faces whose centres lie inside it, and the analytic figures are
// taken at the radius of the same area (effective_radius), since the face count is what moves the air.

#include <vector>

namespace ameoto::reference {

struct SpectrumPoint {
    double ka = 0.0;
    double simulated_db = 0.0;    // re 1 (Pa per m/s, or as stated)
    double analytic_db = 0.0;
    double error_db() const { return simulated_db - analytic_db; }
};

// A circular piston in an infinite rigid baffle, prescribed velocity U(t) (a Gaussian pulse), on-axis
// pressure at z: |p / U| = 2 rho0 c |sin(k (sqrt(z^2 + a^2) - z) / 2)| (Kinsler et al., Fundamentals of
// Acoustics, 4th ed., section 7.4).
struct PistonSetup {
    double radius_m = 0.1;
    double cells_per_radius = 8.0;
    double listener_over_radius = 3.0;   // z / a of the on-axis point
    double ka_low = 0.5, ka_high = 5.0, ka_step = 0.25;
    double margin_over_radius = 1.0;     // air beyond the rim to the absorbing layer
    int pml_cells = 10;
};
struct PistonResult {
    double dx = 0.0, effective_radius = 0.0, listener_z = 0.0;
    long cells = 0, steps = 0;
    std::vector<SpectrumPoint> points;   // |p / U| in dB re 1 Pa s/m
    double worst_error_db() const;
};
PistonResult baffled_piston(const PistonSetup& setup);

// A rigid disc moving broadside in free air (no baffle), prescribed velocity (a Gaussian pulse). Added
// mass from the air's force, m = -Im(F / U) / omega at low ka, against (8/3) rho0 a^3 (Lamb, Hydrodynamics,
// section 108); the on-axis pressure at r against the dipole of moment (8/3) a^3 U, whose far field is
// 4 ka / (3 pi) of the baffled piston's (acoustics.md section 2), with the point dipole's near-field
// factor |1 + 1 / (i k r)| kept (1.05 at kr = 3): |p / U| = rho0 c (2 / (3 pi)) k^2 a^3 / r |1 + 1/(ikr)|.
// With disc_mass_kg > 0 a second run drives the same disc, free, by a force pulse, and the added mass is
// F / (i omega U) - M (the coupling's own check: the air then moves the disc instead of the reverse).
struct DiscSetup {
    double radius_m = 0.1;
    double cells_per_radius = 6.0;
    double listener_over_radius = 8.0;   // r / a of the on-axis point
    double mass_ka = 0.1;                // where the added mass is read
    double ka_low = 0.1, ka_high = 0.5, ka_step = 0.05;
    double margin_over_radius = 1.5;
    int pml_cells = 10;
    double disc_mass_kg = 0.0;           // > 0: also the force-driven run
};
struct DiscResult {
    double dx = 0.0, effective_radius = 0.0, listener_r = 0.0;
    long cells = 0, steps = 0;
    double added_mass = 0.0, lamb_mass = 0.0;            // kg, prescribed motion, at mass_ka
    double force_driven_added_mass = 0.0;                // kg, the free disc driven by a force (0: not run)
    std::vector<double> mass_ka, mass_ratio;             // added mass / Lamb's over ka_low..ka_high
    std::vector<SpectrumPoint> points;                   // |p / U| in dB re 1 Pa s/m
    double mass_error() const { return added_mass / lamb_mass - 1.0; }
    double worst_error_db() const;
};
DiscResult rigid_disc(const DiscSetup& setup);

// Christian, Davis, Tubis, Anderson, Mills & Rossing, J. Acoust. Soc. Am. 76:1336 (1984): the timpani head
// a = 0.328 m, s = 0.2653 kg/m^2, T = 3990 N/m, here on the grid's own faces (5-point Laplacian, fixed rim)
// in free air with no kettle and no baffle. The (m,1) modes, m = 1..5, from the membrane's motion
// projected on J_m(j_m1 r / a) cos(m theta) after a start in the sum of those shapes; the same discrete
// membrane in vacuum for the lowering. Measured ratios to (1,1) (Rossing 1982): 1.48, 1.92, 2.36, 2.78.
struct TimpaniSetup {
    double radius_m = 0.328, areal_density = 0.2653, tension = 3990.0;
    double cells_per_radius = 12.0;
    double duration_s = 0.15;
    double margin_xy_over_radius = 0.5, margin_z_over_radius = 0.5;
    int pml_cells = 8;
    bool air = true;                     // false: the air run is a vacuum run too (for the tests' negative check)
};
struct TimpaniResult {
    double dx = 0.0;
    long cells = 0, steps = 0;
    double vacuum_hz[5] = {}, air_hz[5] = {};
    double air_ratio(int m) const { return air_hz[m - 1] / air_hz[0]; }          // m = 2..5
    double vacuum_ratio(int m) const { return vacuum_hz[m - 1] / vacuum_hz[0]; }
    double lowering() const { return air_hz[0] / vacuum_hz[0]; }
};
TimpaniResult timpani(const TimpaniSetup& setup);
constexpr double timpani_measured_ratio[4] = {1.48, 1.92, 2.36, 2.78};   // (2,1) .. (5,1) over (1,1)

// The absorbing layer's reflection: a point source's pulse in a box, against the same source in a box
// large enough that nothing comes back within the window; the largest difference at listeners near the
// layer (normal and 45 degree grazing), relative to the direct pulse's peak there, in dB.
struct ReflectionSetup {
    double dx = 0.01;
    int half_cells = 12;                 // interior half width of the small box
    int pml_cells = 10;
    double pml_reflection = 1e-4;
};
struct ReflectionResult {
    double normal_db = 0.0, oblique_db = 0.0;
    long cells = 0;
};
ReflectionResult layer_reflection(const ReflectionSetup& setup);

}  // namespace ameoto::reference
