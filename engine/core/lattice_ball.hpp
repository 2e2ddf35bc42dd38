// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A ball of point masses on a face-centred cubic (FCC) lattice, joined to their 12 nearest
// neighbours: the 3-D mass-spring drop of the seed (section 4.2, Fig. 8).
//
// Interface:
//   LatticeBallSpec spec;            // diameter (m), centre, target_masses (0: the seed's rule),
//                                    // density, and the links: kind, stiffness, damping, break force
//   LatticeBall ball = make_lattice_ball(spec);          // a new Body3D (not finalized) + info
//   LatticeBallInfo info = add_lattice_ball(body, spec);  // or append to an existing body
//   info.first_mass, mass_count, first_link, link_count, spacing, node_mass, total_mass, sphere_offset
//   LatticeBallShape shape = lattice_ball_shape(target);  // the geometry alone, for a 1 m diameter ball
//                                                         // centred on its centre of mass: scale by D
//   auto choices = lattice_ball_choices(max_target);      // which shells for every target up to max
//
// Why FCC: every site has 12 equidistant neighbours forming tetrahedra and octahedra, the 3-D analogue
// of the triangular lattice (most isotropic) and the tetrahedral mesh of the seed's Fig. 8 (Van Duyne &
// Smith 1996). Sites are the integer points (i, j, k) with i + j + k even, scaled so that neighbours,
// at offsets (+-1, +-1, 0) and permutations, lie one spacing h apart.
//
// How many masses: the seed gives a drop one mass per 1 mm-diameter drop of volume, so a D mm drop has
// round(D^3) masses (125 for 5 mm; section 5.1.1). A ball of lattice sites cut by a sphere can only take
// counts that fill whole shells of sites around the sphere's centre, so the builder tries five
// high-symmetry centres (a site, an octahedral hole, a tetrahedral hole, a bond midpoint, a triangle's
// centroid), each with its own sequence of shell counts, and takes the count nearest the target. The
// spacing then puts the ball's surface half way between the last shell taken and the next one, so no
// site sits near the surface and rounding cannot flip one in or out. (D = 1 mm gives one mass, spacing
// D.) The sites' mean is then moved onto the requested centre: for the first four centres it already
// is there by symmetry; for the triangle's it is off by sphere_offset along the 3-fold axis.
//
// Mass: each mass is rho (pi D^3 / 6) / count, so the ball's mass is the drop's to rounding. Each link
// has rest length h, the initial distance: the ball starts at rest, unstressed.

#include <cstdint>
#include <limits>
#include <vector>

#include "engine/core/body3d.hpp"
#include "engine/core/physical_constants.hpp"

namespace ameoto {

struct LatticeBallSpec {
    double diameter = 5e-3;                           // m
    Vec3 centre{};                                    // m, where the centre of mass is placed
    int target_masses = 0;                            // 0: round((D / 1 mm)^3), at least 1
    double density = constants::water_density;        // kg/m^3
    LinkKind link_kind = LinkKind::spring;
    double stiffness = 0.0;                           // N/m, each link
    double damping = 0.0;                             // N s/m, each link
    double break_force = Body3D::no_break;            // N, for LinkKind::breakable
};

struct LatticeBallInfo {
    int first_mass = 0, mass_count = 0;   // the ball's masses are first_mass .. first_mass + mass_count - 1
    int first_link = 0, link_count = 0;   // likewise its links
    double spacing = 0.0;                 // m, nearest-neighbour distance (link rest length)
    double node_mass = 0.0;               // kg, each mass
    double total_mass = 0.0;              // kg, density * pi D^3 / 6
    double sphere_offset = 0.0;           // m, from the cutting sphere's centre to the centre of mass
};

struct LatticeBall {
    Body3D body;
    LatticeBallInfo info;
};

// The ball's geometry for a diameter of 1 m, its centre of mass at the origin: add_lattice_ball places
// centre + D * position[i] and links link_a[l] - link_b[l] (in this order) at rest length D * spacing.
struct LatticeBallShape {
    std::vector<Vec3> position;                   // per mass, m per m of diameter
    std::vector<std::int32_t> link_a, link_b;     // each nearest-neighbour pair once
    double spacing = 0.0;                         // nearest-neighbour distance per m of diameter
    double sphere_offset = 0.0;                   // centre of mass to cutting sphere's centre, per m
    int centre_kind = 0;                          // which of the five candidate centres (identity:
    long long last_shell_key = 0;                 // two shapes with equal kind and key are the same)
    int mass_count() const { return static_cast<int>(position.size()); }
    int link_count() const { return static_cast<int>(link_a.size()); }
};

// The seed's mass count for a drop of diameter D: round((D / 1 mm)^3), at least 1.
int seed_mass_count(double diameter_m);

// Which shells of which centre give the count nearest a target (what lattice_ball_shape picks).
struct LatticeBallChoice {
    int centre_kind = 0;
    long long last_key = 0, next_key = 0;   // 36 x squared radius of the last shell taken, of the next
    int count = 1;                          // masses
};

// target_masses <= 0: one mass. Allocates; about 2 ms at 512 masses.
LatticeBallShape lattice_ball_shape(int target_masses);
// The choice for every target 1..max_target (element t - 1), from one enumeration: for a table of
// shapes (the drop pool's), far faster than max_target calls of lattice_ball_shape(int).
std::vector<LatticeBallChoice> lattice_ball_choices(int max_target);
LatticeBallShape lattice_ball_shape(const LatticeBallChoice& choice);

LatticeBallInfo add_lattice_ball(Body3D& body, const LatticeBallSpec& spec);
LatticeBall make_lattice_ball(const LatticeBallSpec& spec);

}  // namespace ameoto
