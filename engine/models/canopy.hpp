// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// An umbrella canopy: N identical panels, each a membrane fixed on its two ribs and free at its hem,
// on a spherical cap.
//
// Interface:
//   Canopy canopy(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), time_step_s);   // allocates;
//   Canopy c(geometry, material, T, NetworkOptions{...});   // integrator and stability policy per panel;
//                                  // throws std::invalid_argument (bad geometry or material, with the
//                                  // reason) or StabilityError (refused: the bound in the message)
//   Canopy::check(geometry, material, T, options)   // the same verdict without building: MaterialCheck
//   canopy.locate(x, y)            // -> {panel, node} under a point in canopy coordinates, or panel -1;
//                                  // no allocation, no trigonometry in the common case (see canopy.cpp)
//   canopy.sample_point(rng)       // a point uniform over the canopy's plan area (for rain)
//   canopy.apply_force(hit, N)     // a force along the node's normal n for the next step
//   canopy.step(panel_forces)      // one sample: fills one net force per panel (N); no allocation
//   canopy.reset_unstable()        // runtime guard: resets any panel whose state went non-finite or
//                                  // whose energy ran away (core/stability.hpp); returns how many
//   canopy.rest_position(k, i), canopy.normal(k, i)     // node i of panel k: 3-D rest point, unit normal
//   canopy.node_position(k, i)     // rest + u n: where the membrane is now
//   canopy.displacement(k, i), canopy.normal_velocity(k, i)   // u (m) and du/dt (m/s) along n
//   canopy.displacement_range()    // {lowest, highest} u over every node: bounds for a collision
//                                  // broad phase (drop_on_canopy_collide.cpp); no allocation
//   canopy.rest_height(x, y), canopy.surface_normal(x, y)     // the rest surface over a plan point
//   ---- per panel (the state lives in the lanes when laned(); panel(k).network then holds only the
//        panel's arrays, stability report and options, its state stays at rest: read these instead) ----
//   canopy.panel_positions(k, out), canopy.panel_velocities(k, out)   // u, du/dt of every node, out[node]
//   canopy.panel_finite(k), canopy.panel_energy(k), canopy.panel_guard_resets(k)
//   canopy.stability()             // every panel's StabilityReport (they are the same body)
//   ---- every panel at once, node-major (the far field, the collision broad phase) ----
//   canopy.lanes()                 // the layout's stride: panels rounded up to a multiple of 4
//   canopy.velocities(out)         // out[node * lanes() + panel] (padding lanes: 0)
//   canopy.laned(), canopy.set_portable_kernels(true), canopy.set_kernel_ceiling(32), canopy.avx2_kernels(),
//   canopy.kernel_width()          // the lanes' kernels (laned_network.hpp): 16, 32 or 64-byte vectors
//   ---- in air (air_canopy.hpp) ----
//   canopy.set_air(build_air_canopy_modes(canopy, T))   // build phase: from now on the canopy runs its
//                                  // modes in air instead of the lattice (nullptr: the lattice again);
//                                  // every reading above then comes from the modes, the state at rest
//   canopy.in_air(), canopy.air_modes(), canopy.air_state()
//   canopy.contact_mass(k, i)      // kg: the node's mass as an impact meets it (the lattice's mass in
//                                  // vacuum; in air 1 / sum_k phi_ik^2, air_canopy.hpp)
// In air: step() fills panel_forces with 0 (the panels' net forces are not formed: the dipole radiation,
// dipole_radiation.hpp, reads the modes), displacement_range() is the bound -b..b with
// b = AirCanopyState::displacement_bound (the broad phase needs only bounds), and reset_unstable()
// resets every mode when any went non-finite (counted once per panel in panel_guard_resets).
//
// Stepping: the panels are identical networks, so with explicit Verlet or symplectic Euler (the default
// and the cheap end of the accuracy chart) the canopy steps them together as SIMD lanes
// (core/integrators/laned_network.hpp: one pass over the links for every panel, each panel's output
// bit-identical to its own TransverseNetwork); with trapezoidal, backward Euler or modal it steps one
// TransverseNetwork per panel. The runtime guard stays per panel either way.
//
// Geometry (seed section 5.1.2, Fig. 10-11): seen from above, panel k is the triangle between the
// umbrella's centre and two neighbouring rib tips at plan radius R, centred on azimuth 2 pi k / N.
// Canopy coordinates: x, y in m from the shaft, horizontal; z up, 0 at the top of the shaft. The plan
// area is N R^2 sin(2 pi / N) / 2 (0.707 m^2 for 8 panels of 0.5 m).
// Curvature: the rest surface is a spherical cap of radius Rc centred on the shaft,
//   z(x, y) = sqrt(Rc^2 - r^2) - Rc = -r^2 / (sqrt(Rc^2 - r^2) + Rc),   r^2 = x^2 + y^2,
//   n(x, y) = (x / Rc, y / Rc, sqrt(1 - r^2 / Rc^2))   (unit, outward and up),
// Rc = infinity (the default) is flat: z = 0, n = (0, 0, 1). Rc must exceed R (the rim slope is
// asin(R / Rc)). Every node has a 3-D rest position (its plan point lifted onto the cap) and the cap's
// normal there; the membrane moves along that normal, so a node is at rest + u n.
// Approximation (shallow shell, Marguerre's theory at zeroth order): the lattice, its masses (s times
// the node's plan area) and its springs are those of the flat plan-view panel; only the direction of
// motion and the positions are curved. Neglected: the coupling of transverse motion to in-plane
// stretching through the curvature (curvature stiffening, which raises the lowest modes of a shell),
// and the surface's larger true area (a factor 1 / n_z, up to 1 / cos(asin(R / Rc)) at the rim:
// 3.3 % for Rc = 2 m, 15 % for Rc = 1 m, with R = 0.5 m). Valid while the slope stays small.

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/core/integrators/laned_network.hpp"
#include "engine/core/random.hpp"
#include "engine/models/air_canopy.hpp"
#include "engine/models/membrane.hpp"

namespace ameoto {

struct CanopyGeometry {
    int panels = 8;
    double radius_m = 0.5;                  // plan radius of the rib tips
    int masses_per_panel = 50;
    double curvature_radius_m = std::numeric_limits<double>::infinity();   // Rc; infinity: flat
    bool operator==(const CanopyGeometry&) const = default;
};

struct DisplacementRange {
    double lowest = 0.0, highest = 0.0;   // m
};

struct CanopyHit {
    int panel = -1;   // -1: the point is not on the canopy
    int node = -1;
};

class Canopy {
public:
    Canopy(const CanopyGeometry& geometry, const MembraneMaterial& material, double time_step_s,
           const NetworkOptions& options = NetworkOptions{});

    static MaterialCheck check(const CanopyGeometry& geometry, const MembraneMaterial& material, double time_step_s,
                               const NetworkOptions& options = NetworkOptions{});

    CanopyHit locate(double x, double y) const;
    Point2 sample_point(Random& rng) const;
    void apply_force(CanopyHit hit, double newtons);
    void step(double* panel_forces);
    int reset_unstable();

    int panel_count() const { return static_cast<int>(panels_.size()); }
    int nodes_per_panel() const { return nodes_; }
    double panel_azimuth(int panel) const;      // rad, direction of the panel's centre line
    Point2 panel_centroid(int panel) const;     // m, canopy coordinates
    double area() const;                        // m^2, plan area of all panels
    double node_area() const { return panels_.front().lattice.node_area; }   // m^2, plan area per node
    const CanopyGeometry& geometry() const { return geometry_; }
    const Membrane& panel(int k) const { return panels_[static_cast<std::size_t>(k)]; }

    Vec3 rest_position(int panel, int node) const { return rest_[index(panel, node)]; }
    Vec3 normal(int panel, int node) const { return normal_[index(panel, node)]; }
    Vec3 node_position(int panel, int node) const;
    double displacement(int panel, int node) const;
    double normal_velocity(int panel, int node) const;
    DisplacementRange displacement_range() const;   // over every node (NaN states are passed over)
    double rest_height(double x, double y) const;
    Vec3 surface_normal(double x, double y) const;
    bool flat() const { return !(geometry_.curvature_radius_m < std::numeric_limits<double>::infinity()); }

    void panel_positions(int panel, double* out) const;
    void panel_velocities(int panel, double* out) const;
    bool panel_finite(int panel) const;
    double panel_energy(int panel) const;   // J
    std::uint64_t panel_guard_resets(int panel) const;
    const StabilityReport& stability() const { return panels_.front().network.stability(); }
    int lanes() const { return lanes_; }
    void velocities(double* out) const;
    bool laned() const { return laned_; }
    // The lanes' state when laned() and not in air (else nullptr): the far field reads x and the previous
    // sub-step's x to form the velocities and accelerations in one pass (radiation.cpp).
    const LanedNetwork* lanes_state() const { return laned_ && !air_ ? &lanes_state_ : nullptr; }
    void set_portable_kernels(bool on) { lanes_state_.set_portable_kernels(on); }
    void set_kernel_ceiling(int bytes) { lanes_state_.set_kernel_ceiling(bytes); }
    int kernel_width() const { return laned_ ? lanes_state_.kernel_width() : 0; }
    bool avx2_kernels() const { return laned_ && lanes_state_.avx2_kernels(); }

    void set_air(std::shared_ptr<const AirCanopyModes> modes);
    bool in_air() const { return air_ != nullptr; }
    const AirCanopyModes* air_modes() const { return air_.get(); }
    const std::shared_ptr<const AirCanopyModes>& shared_air_modes() const { return air_; }   // build phase: a key that keeps them alive
    const AirCanopyState& air_state() const { return air_state_; }
    double contact_mass(int panel, int node) const {
        if (air_) return air_->contact_mass[index(panel, node)];
        return panels_[static_cast<std::size_t>(panel)].network.mass(node);
    }

private:
    // Local panel frame: hem along y = 0 from (-w, 0) to (w, 0), apex (the shaft) at (0, h).
    Point2 to_local(int panel, double x, double y) const;
    Point2 to_canopy(int panel, Point2 local) const;
    int panel_at(double x, double y) const;          // locate's panel: the azimuth's nearest centre line
    int panel_by_atan2(double x, double y) const;    // the same by atan2 (the definition; the fallback)
    bool inside_outline(Point2 local) const;         // polygon_contains(outline_, local), precomputed
    DisplacementRange laned_displacement_range() const;
    std::size_t index(int panel, int node) const {
        return static_cast<std::size_t>(panel) * static_cast<std::size_t>(nodes_) + static_cast<std::size_t>(node);
    }
    CanopyGeometry geometry_;
    double half_width_ = 0.0, height_ = 0.0;
    int nodes_ = 0;
    std::vector<PolygonEdge> outline_;
    std::vector<Membrane> panels_;
    bool laned_ = false;
    int lanes_ = 4;
    LanedNetwork lanes_state_;          // every panel's state when laned_
    mutable std::vector<double> lane_low_, lane_high_;   // displacement_range()'s per-lane extremes
    std::vector<Vec3> rest_, normal_;   // per panel and node, panel-major
    std::shared_ptr<const AirCanopyModes> air_;   // in air: the modes (shared by copies: immutable)
    AirCanopyState air_state_;
    std::uint64_t air_resets_ = 0;
    mutable std::vector<double> displacements_;   // displacement_range()'s scratch: one panel's u
    // locate()'s tables, set by the constructor so that locate needs no trigonometry: per panel the
    // cosine and sine of its azimuth (to_local); the sector boundaries' unit vectors, boundary k at
    // azimuth (k - 1/2) 2 pi / N for k = 0..N (panel k lies between boundaries k and k + 1); and the
    // outline's edges as polygon_contains computes them.
    struct OutlineEdge {
        double ax = 0.0, ay = 0.0, ex = 0.0, ey = 0.0, length = 0.0;
    };
    std::vector<double> cos_azimuth_, sin_azimuth_;
    std::vector<Point2> boundary_;
    std::array<OutlineEdge, 3> edges_{};
};

}  // namespace ameoto
