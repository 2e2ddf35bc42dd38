// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The air's mass on a thin flat screen (a membrane) in unbounded air, loaded on both faces, with no
// baffle: the incompressible added-mass matrix of its moving cells, by the vortex-ring (uniform doublet
// panel) method.
//
// Interface (build phase only: everything here allocates; never on the audio thread):
//   ScreenSampling s = sample_screen(lo, hi, h, owner);   // squares of side h over the box [lo, hi],
//                                                         // each owned by owner(centre): a cell index
//                                                         // 0..N-1, or -1 where there is no screen
//   AddedMass a = screen_added_mass(s, rho0);             // a.matrix (N x N, kg), a.area (m^2 per
//                                                         // cell), a.centroid (collocation points)
//   AddedMass c = canopy_added_mass(canopy, rho0);        // the umbrella's nodes, panel-major
//                                                         // (index panel * nodes + node), converged
//                                                         // in the cell size (0.3 s of CPU): use this
//   AddedMass o = canopy_added_mass(canopy, h, rho0);     // the same by one ring per node (squares of
//                                                         // side h): about 6 % too much air
//   a.matrix * acceleration = the force the air puts on each cell, with the sign reversed: the
//   equation of motion in air is (M + M_a) u'' + C u' + K u = f.
//   AirLoadedModes m = air_loaded_modes(canopy, a);       // the whole canopy's modes in air:
//                                                         // K phi = omega^2 (M + M_a) phi
//
// Method. A thin screen moving along its normal with velocity w(x, y) in incompressible, irrotational
// air has a potential phi that jumps across it by mu = phi(top) - phi(bottom); the screen is a doublet
// sheet of strength mu. A cell of uniform mu is the same flow as a vortex ring of circulation -mu round
// the cell's edge (Katz & Plotkin, Low-Speed Aerodynamics, 2nd ed., section 10.4: a constant-strength
// doublet panel is a vortex ring). The normal velocity at collocation point i (the centroid of cell i)
// is then w_i = sum_j G_ij Gamma_j, G_ij the Biot-Savart velocity of the unit counter-clockwise ring
// round cell j at point i (Katz & Plotkin eq. 10.115, the straight segment). Linearised Bernoulli,
// p = -rho0 d(phi)/dt, gives the pressure jump Delta p = p(top) - p(bottom) = -rho0 d(mu)/dt, and the
// force up on cell i is -Delta p_i A_i. With Gamma = -mu and the cells moving with accelerations a,
//   F_i = -rho0 A_i (G^-1 a)_i,   so   M_a = rho0 diag(A) G^-1   (then symmetrised: (M_a + M_a') / 2;
// collocation leaves it symmetric only to the discretisation's order).
// Why incompressible: the canopy's membrane waves are subsonic (129 m/s on nylon, slower still with
// the air's mass) so the air near it moves as an evanescent, nearly incompressible layer whose mass per
// area is rho0 / sqrt(kappa^2 - k^2) per face (acoustics.md section 1): for the lowest, most loaded
// modes kappa / k is 6 or more, a correction under 1.5 % in mass; for the highest modes of a 50-mass
// panel (kappa / k about 2.7, loaded by about a third of their mass) some 2 % in frequency. The
// radiation that compressibility adds is computed separately (air_radiation.hpp).
// Cells: every square of the sampling belongs to one cell; a cell's ring is the sum of its squares'
// rings, so only edges between different owners (or the outside) are kept, merged along straight runs.
// Accuracy (tests/engine/models/air_loading_test.cpp): a disc's added mass against Lamb's
// (8/3) rho0 a^3 (Hydrodynamics, section 108), and the modes of Christian et al.'s timpani head in air;
// the umbrella's first 10 panel modes against the FDTD reference (tests/engine/reference/
// canopy_modes_test.cpp, docs/canopy-air.md: -1.5 .. +0.9 %, mode 4 -3.9 %).

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/triangular_lattice.hpp"

namespace ameoto {

class Canopy;

struct ScreenSampling {
    Point2 origin;            // the lower-left corner of square (0, 0), m
    double side = 0.0;        // m
    int nx = 0, ny = 0;       // squares along x and y
    int cells = 0;            // owners are 0..cells-1
    std::vector<int> owner;   // [j * nx + i], -1: no screen there
};

struct AddedMass {
    Eigen::MatrixXd matrix;     // kg, symmetric
    Eigen::VectorXd area;       // m^2 per cell: its squares' area
    std::vector<Point2> centroid;
    // N > 1 when the cells are N copies of one sector turned by 2 pi / N (cell p * size / N + i is sector
    // 0's cell i turned by 2 pi p / N): canopy_added_mass sets the panel count. radiation_damping then
    // reads the phases of one sector's directions only.
    int rotational_order = 1;
};

// Throws std::invalid_argument if h <= 0, the box is empty, or a cell index is out of range, and
// std::runtime_error if some cell owns no square (h too coarse for the cells).
ScreenSampling sample_screen(Point2 lo, Point2 hi, double h, int cells, const std::function<int(Point2)>& owner);
AddedMass screen_added_mass(const ScreenSampling& sampling, double air_density);

// The umbrella's canopy seen from above (a flat canopy; a curved one is taken as its plan: the shallow
// shell's approximation, canopy.hpp): each square belongs to the node Canopy::locate gives there.
AddedMass canopy_added_mass(const Canopy& canopy, double square_side_m, double air_density);

// The umbrella's air mass converged in the cell size, for the server (the call above keeps one ring per
// node, whose O(h) over-estimate is about +6 % at the umbrella's 45 mm cells). Each panel's triangle is
// cut into rows x (rows + 1) / 2 nearly square sub-cells, each a ring of its own moving with the node that
// Canopy::locate gives at its centre; the cells' forces are summed per node (M_a = P' M_cells P, P the
// 0/1 owner matrix). The panels are one triangle turned by 2 pi / N, so the cells' G is block circulant:
// it is solved on the N Fourier modes over the panel index, one panel's size each. With extrapolate,
// the same at rows / 2 and M_a = (r2 M(r2) - r1 M(r1)) / (r2 - r1) (Richardson; the error is O(h)).
// area and centroid are the finer level's. Throws std::invalid_argument for rows < 2 or a density <= 0,
// std::runtime_error if some node owns no sub-cell at rows / 2 (more rows).
struct CanopyAirMassOptions {
    int rows = 24;            // the finer level's rows from the shaft to the hem (300 sub-cells a panel)
    bool extrapolate = true;  // with rows / 2 (78 a panel): Richardson
    bool operator==(const CanopyAirMassOptions&) const = default;
};
AddedMass canopy_added_mass(const Canopy& canopy, double air_density, const CanopyAirMassOptions& options = {});

// The modes of the whole canopy (every panel; node index panel * nodes + node) in air, from the
// panels' own K and M (its lattice) and the air's M_a: mass-normalised, Phi' (M + M_a) Phi = I, with
// each mode's decay rate s_k = (Phi' C Phi)_kk / 2 from the material's damping C = alpha M + beta K
// (classical modal damping: in air C is no longer proportional to the mass matrix). Throws
// std::invalid_argument when a does not match the canopy's node count, std::runtime_error if the
// eigen-solve fails.
struct AirLoadedModes {
    Eigen::VectorXd omega;          // rad/s, ascending
    Eigen::MatrixXd shapes;         // [node, mode]
    Eigen::VectorXd damping_rate;   // 1/s
};
AirLoadedModes air_loaded_modes(const Canopy& canopy, const AddedMass& air);

// Each mode's decay rate by radiation (1/s), for a flat screen: the mode's pressure jump, from the
// incompressible solution (Delta p_i A_i = (M_a phi)_i q''), radiates as a sheet of dipoles along the
// normal; at frequency w = c k the far field at direction (theta, psi) is
//   p = (i k cos(theta) e^(-ikR) / 4 pi R) S,   S = sum_i (M_a phi)_i e^(i k r . y_i) q'',
// and the power W = (1 / 2 rho0 c) integral |p|^2 R^2 d(Omega) against the mode's energy
// E = w^2 Q^2 / 2 (mass-normalised) gives
//   s_rad = W / 2E = k^2 w^2 / (32 pi^2 rho0 c) integral cos^2(theta) |S / q''|^2 d(Omega)
// (for a rigid body, S = the force it puts on the air, and W is a point force's k^2 F^2 / 24 pi rho0 c).
// The integral over both half-spaces (|S| is even in cos(theta)) by Gauss-Legendre in cos(theta) and
// the trapezoid rule in azimuth. Approximation: the source is the incompressible near field's pressure
// jump (ka small, or a subsonic mode whose radiating part is small); the radiation's reaction on the
// modes' frequencies is left out.
Eigen::VectorXd radiation_damping(const AirLoadedModes& modes, const AddedMass& air, double air_density,
                                  double speed_of_sound, int polar_points = 12, int azimuth_points = 32);

// The velocity along +z at p induced by a vortex segment a -> b of unit circulation, all in one plane
// (Biot-Savart; 0 on the segment's line). Exposed for its test.
double ring_segment_velocity(Point2 p, Point2 a, Point2 b);

}  // namespace ameoto
