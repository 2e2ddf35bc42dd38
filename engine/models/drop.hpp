// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One drop: a 3-D lattice of masses calibrated from its liquid (seed sections 3.1, 4.4, 5.1.1).
//
// Interface:
//   auto lattice = drop_lattice(target);                     // shared, cached; off the audio thread
//   auto table = drop_lattices(max_target);                  // all targets 1..max at once
//   StretchMode m = stretch_mode(shape);                     // lambda_2 computed (what drop_lattice caches)
//   auto t = tabulated_stretch_mode(shape);                  // ... or from the committed table (nullopt: absent)
//   DropCalibration c = calibrate_drop(D, liquid);           // off the audio thread (uses drop_lattice)
//   DropCalibration c = calibrate_drop(*lattice, D, liquid, options);   // closed form: audio-safe
//   DropInfo info = add_drop(body, *lattice, c, centre, velocity, DragPreset::quadratic);
//                                                            // no allocation within body.reserve()
//   Drop drop = make_drop(D, liquid, centre);                // a Body3D of its own: gravity on,
//                                                            // symplectic Euler, arrival speed, not finalized
//   set_piece_drag(body, info, c, components, preset);       // after a breakup: each piece's own drag
//   Vec3 q = drop_orientation(p, tilted);                    // a lattice point as add_drop places it
//   rayleigh_frequency(D, liquid, n), lamb_decay_time(D, liquid, n), arrival_speed(D, density)
//
// Masses. One mass per 1 mm-diameter drop of volume (seed 5.1.1): target N = round((D / 1 mm)^3),
// at least 1, on the FCC lattice of lattice_ball.hpp (which takes the whole-shell count nearest the
// target: 1, 7, 28, 122, 512 masses at 1, 2, 3, 5, 8 mm). Each mass is rho (pi D^3 / 6) / N: the drop's
// mass is exact. Below about 1.15 mm the drop is a single mass: it falls and strikes, but has no shape
// and cannot break.
//
// Links: calibrated so that the free drop oscillates at Rayleigh's frequency. A liquid drop's shape
// modes (Rayleigh 1879; Lamb 1932, art. 275) are
//     omega_n^2 = n (n - 1) (n + 2) sigma / (rho a^3),   a = D / 2;   n = 2: omega_2^2 = 8 sigma / (rho a^3)
// (122 Hz at 2 mm, 66 Hz at 3 mm, 31 Hz at 5 mm for water). The lattice with every link of stiffness k
// and every mass m has modes omega^2 = lambda k / m, where lambda are the eigenvalues of the stiffness
// matrix K (3N x 3N; each link adds u u^T between its masses, u its unit axis) for k = m = 1: a
// property of the lattice's shape alone. So
//     k = m omega_2^2 / lambda_2
// where lambda_2 is the lattice's own n = 2 mode. Which mode: the one a volume-preserving stretch
// along z, u = (-x/2, -y/2, z), excites most (the liquid's n = 2 shape, P2(cos theta)): the lattice's
// eigenvalue with the largest share of that stretch (79-94 % of it at 7-512 masses). Not the lowest
// non-zero eigenvalue: a lattice of springs is an elastic solid, with torsional and surface modes a
// liquid does not have, and these lie lower (3 mm: lowest 0.086 against the stretch mode's 0.432, so
// calibrating on the lowest would put the stretch oscillation 2.2 times above Rayleigh). lambda_2 is
// found by shift-invert Lanczos (Ericsson & Ruhe 1980) started from that stretch, with the six rigid
// motions projected out: the Ritz values' weights (first components squared) are the stretch's
// spectral measure, and the largest one is the mode. A sparse LDL^T of K + s I makes it fast (about
// 0.1 s at 512 masses, against 5 s for the dense eigensolver; 2-4 s for all 122 shapes up to 8 mm),
// computed once per lattice shape and cached for the process. Every shape up to 8 mm is tabulated
// (stretch_mode_table.hpp: the same bits, committed), so the process computes only larger ones.
// Tests: the Lanczos value agrees with the dense eigensolver; a simulated free drop stretched by 1 %
// oscillates within 10 % of Rayleigh (measured values in docs/drop.md, "The lattice drop").
//
// Viscous damping (Lamb 1932, art. 355): mode n decays as exp(-t / tau), tau = a^2 / ((n-1)(2n+1) nu),
// nu = mu / rho; n = 2: tau = a^2 / (5 nu). A damper z = beta k on every link makes the damping
// matrix C = beta K, so each mode decays at beta omega^2 / 2; beta = 2 / (tau omega_2^2) gives the n = 2
// mode Lamb's rate:  z = 2 k / (tau omega_2^2) = (5/4) (mu a / sigma) k. Higher modes decay faster (as
// omega^2, where Lamb's rate grows as n^2). Lamb's result holds for weak viscosity: when
// 1 / tau > omega_2 (Ohnesorge number mu / sqrt(rho sigma a) above about 0.57) the mode is overdamped
// here, as in a real viscous drop, but relaxes about 3 times faster than Chandrasekhar's (1959)
// viscous limit (0.26 sigma / (mu a)): heavy oil is such a liquid.
//
// Break threshold: the seed breaks a link when its load passes "the surface tension of water" (4.4),
// a force per length. Here a link stands for the liquid neck that joins two neighbouring parcels one
// spacing h apart; a liquid thread of radius r carries an axial force of 2 pi r sigma (surface
// tension around it) minus pi r^2 sigma / r (its Laplace pressure), pi r sigma. With r = h / 2:
//     F_break = pi sigma h / 2
// A bond breaks when its spring pulls harder than that, i.e. when stretched by F_break / k (1.18 h at
// 5 mm, 0.33 h at 2 mm: k itself scales with sigma, so the breaking strain depends only on the lattice,
// 3 N lambda_2 / 64). Compression never breaks a bond, and the damper (viscosity) resists stretching
// without counting towards the tear (body3d.hpp, cohesive links).
//
// Incompressibility: a liquid converts an impact's downward momentum into sideways flow because it
// cannot be compressed, and springs calibrated from surface tension are 1e3 times too soft for that
// (a drop of them hitting a floor folds into a heap and bounces whole). Each link therefore carries a
// repulsive core: below core_length (0.9 h) it pushes with stiffness k_c = m (core_speed / h)^2, i.e.
// a neighbour closing at core_speed is stopped within about one spacing; core_speed = 15 m/s, above the
// fastest raindrop (9.2 m/s). 0.9 h, not h: the core stays clear of small oscillations (the calibration
// above is untouched), and a cube-axis compression (FCC's 45-degree links shorten least) reaches it at
// 21 % strain; below 1/sqrt 2 = 0.71 h it would never be reached by such a compression. Its frequency
// sets the drop's time step: 1 sub-step at 48 kHz (2 for heavy oil from 3 mm: its dampers).
//
// Fall. Air drag per mass (body3d_drag.hpp): quadratic (default; Beard's C_d for the drop's diameter,
// b = rho_air C_d (pi D^2 / 4) / 2 shared equally by the N masses, so the intact drop has the drag of a
// drop of its size), seed_linear (the seed's c = 1.77e-8 kg/s per mass: a 1 mm mass would fall at
// m g / c = 290 m/s, 70 times too fast, so it is not the default), or none. After a breakup each piece
// of n masses should have the drag of a drop of its own volume, D (n / N)^(1/3): set_piece_drag() sets
// b = drop_quadratic_drag(D_piece) / n on its masses (no allocation; the pool calls it). For liquids
// other than water C_d is water's (same shape). Arrival speed: Gunn & Kinzer's terminal speed
// (terminal_speed.hpp) times sqrt(rho / rho_water) (the force balance m g = b v^2 at the same C_d).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/lattice_ball.hpp"
#include "engine/models/liquid.hpp"

namespace ameoto {

class ConnectedComponents;

enum class DragPreset : std::uint8_t { quadratic, seed_linear, none };

struct DropOptions {
    bool core = true;             // the incompressible core on every link
    bool tilted = false;          // the lattice turned to a generic orientation (drop_orientation below)
    double core_length = 0.9;     // of the spacing h
    double core_speed = 15.0;     // m/s: k_c = m (core_speed / h)^2
};

// A drop's lattice shape (1 m diameter, centred on its centre of mass) and its n = 2 eigenvalue.
struct DropLattice {
    LatticeBallShape shape;
    double lambda2 = 0.0;         // eigenvalue of the n = 2 mode for k = m = 1 (0 for one mass)
    double weight2 = 0.0;         // the share of the n = 2 stretch that mode carries (0..1)
    int mass_count() const { return shape.mass_count(); }
};

// The lattice for a target mass count (1..200000): built and analysed once per shape, then shared
// (thread-safe cache). Allocates and may take 0.1 s: never on the audio thread.
std::shared_ptr<const DropLattice> drop_lattice(int target_masses);
// Every target 1..max_target (element t - 1) from one enumeration of the lattice: the pool's table.
std::vector<std::shared_ptr<const DropLattice>> drop_lattices(int max_target);

// The n = 2 eigenvalue and weight of a shape, computed afresh (drop_lattice caches it).
struct StretchMode {
    double lambda = 0.0, weight = 0.0;
};
StretchMode stretch_mode(const LatticeBallShape& shape);
// The same from the committed table (stretch_mode_table.hpp), nullopt for a shape it does not hold:
// drop_lattice takes this, and computes only the shapes the table lacks. No allocation.
std::optional<StretchMode> tabulated_stretch_mode(const LatticeBallShape& shape);

struct DropCalibration {
    double diameter = 0.0;          // m
    double density = 0.0, surface_tension = 0.0, viscosity = 0.0;   // the liquid's
    int masses = 0;
    double node_mass = 0.0;         // kg
    double total_mass = 0.0;        // kg, rho pi D^3 / 6
    double spacing = 0.0;           // m, link rest length h
    double rayleigh_hz = 0.0;       // f_2
    double lambda2 = 0.0;
    double stiffness = 0.0;         // N/m, k = m omega_2^2 / lambda_2 (0 for one mass)
    double decay_time = 0.0;        // s, Lamb's tau for n = 2
    double damping = 0.0;           // N s/m, z = 2 k / (tau omega_2^2)
    double break_force = 0.0;       // N, pi sigma h / 2
    double core_length = 0.0;       // m
    double core_stiffness = 0.0;    // N/m (0: no core)
    double arrival_speed = 0.0;     // m/s, terminal speed of a drop of this size and density
    bool tilted = false;            // DropOptions::tilted: add_drop turns the lattice (drop_orientation)
};

// Where a lattice point p (drop_lattice's frame) is put in the drop: p itself, or tilted: the frame
// turned so that its vertical is the generic direction (1, g, g^2) / |.|, g the golden ratio, which no
// plane of the FCC lattice is perpendicular to. Upright, the lattice meets a flat surface a whole plane
// of masses at once (a 2 mm drop's 7 masses arrive as 2, 4 and 1); tilted, every mass at its own
// height, so a wet impact's force (wet_impact.hpp) is the sum of parcels arriving one after another,
// as a liquid's does, rather than a few spikes. Audio-safe.
Vec3 drop_orientation(Vec3 p, bool tilted);

double rayleigh_frequency(double diameter, const Liquid& liquid, int n = 2);   // Hz
double lamb_decay_time(double diameter, const Liquid& liquid, int n = 2);      // s
double arrival_speed(double diameter, double density);                          // m/s

// Closed form from the lattice: no allocation, audio-safe.
DropCalibration calibrate_drop(const DropLattice& lattice, double diameter, const Liquid& liquid,
                               const DropOptions& options = {});
// Looks the lattice up (drop_lattice): off the audio thread.
DropCalibration calibrate_drop(double diameter, const Liquid& liquid, const DropOptions& options = {});

struct DropInfo {
    int first_mass = 0, mass_count = 0;
    int first_link = 0, link_count = 0;
};

// Appends the drop's masses (at centre + D p, all at `velocity`) and cohesive links to `body`, with
// the preset's drag. Gravity, integrator and finalize() are the caller's. No allocation while the body
// has reserved capacity.
DropInfo add_drop(Body3D& body, const DropLattice& lattice, const DropCalibration& calibration, Vec3 centre,
                  Vec3 velocity, DragPreset drag);

// After the body's components were computed: each piece of n masses gets a drop of its volume's
// quadratic drag (preset quadratic; other presets are per mass and stay). No allocation.
void set_piece_drag(Body3D& body, const DropInfo& info, const DropCalibration& calibration,
                    const ConnectedComponents& components, DragPreset drag);

struct Drop {
    Body3D body;
    DropCalibration calibration;
    DropInfo info;
    std::shared_ptr<const DropLattice> lattice;
};

// A drop in a body of its own: gravity on, symplectic Euler, moving at `velocity` (default: straight
// down at its arrival speed). Not finalized: add floors or forces, then body.finalize(T).
Drop make_drop(double diameter, const Liquid& liquid, Vec3 centre, std::optional<Vec3> velocity = std::nullopt,
               DragPreset drag = DragPreset::quadratic, const DropOptions& options = {});

}  // namespace ameoto
