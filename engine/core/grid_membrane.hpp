// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A membrane on a triangular lattice, stored as a regular 2-D grid and stepped with the explicit
// CORDIS scheme as a stencil: the fast path for large membranes (thousands of masses).
//
// Interface:
//   GridMembrane g(GridMembraneBody{node_mass_kg, alpha_per_s, beta_s});   // build phase (allocates)
//   int n = g.add_node(i, j);             // a mass at axial lattice coordinates (i, j)
//   g.add_link(a, b, stiffness_N_per_m);  // a and b must be lattice neighbours (see Layout)
//   g.add_anchor(a, stiffness);           // a spring to a fixed point (u = 0)
//   g.finalize(time_step_s);              // grid layout, coefficients, sub-steps; allocates
//   ---- render phase: never allocates ----
//   g.apply_force(n, newtons);            // external force for the next step
//   double f = g.step();                  // one output sample; net force on all masses (N)
//   g.position(n), g.velocity(n), g.stability(), g.reset(), g.finite()
//
//   GridMembrane g = grid_membrane_over(lattice, areal_density, tension, alpha, beta, time_step_s);
//       // the body build_membrane makes over that lattice (models/membrane.hpp), node n = node n
//   std::vector<AxialIndex> a = axial_coordinates(lattice);   // (i, j) of each lattice node
//
// Physics: TransverseNetwork's explicit Verlet (transverse_network.hpp) for a body with Rayleigh
// damping C = alpha M + beta K (models/membrane.hpp): every node has the same mass m and a damper
// alpha m to the ground; every link and anchor of stiffness k carries a damper beta k. With
// v = (x[n] - x[n-1]) / T the force is F = -K (x + beta v) - alpha M v + f, so the scheme
// x[n+1] = 2 x[n] - x[n-1] + T^2 F / m needs one stencil over y = x + (beta / T) d, d = x[n] - x[n-1]:
//   d[n+1] = (1 - alpha T) d + sum_j c_ij y_j - cd_i y_i + (T^2 / m) f_i,   c = T^2 k / m,
//   y[n+1] = y - (beta / T) d + (1 + beta / T) d[n+1]                      (x = y - (beta / T) d)
// (T: the sub-step; cd_i = sum of i's c plus its anchors'). The state is (y, d), not (x, x[n-1]):
// adding the small d[n+1] - d to d rather than x[n+1] to 2x - x[n-1] keeps float's rounding away
// from the low modes.
// Same output as TransverseNetwork over the same body: 1e-15 .. 2e-13 of the peak in double
// (tests/engine/core/grid_membrane_test.cpp). Net force: the links cancel in pairs, so it is
// f - sum k_a y (anchors) - alpha m sum v, with sum d carried by its own exact recursion
// sum d[n+1] = (1 - alpha T) sum d - (T^2 / m) sum k_a y + (T^2 / m) sum f (no sum over the grid).
// Stability: TransverseNetwork's default rule (physics.md section 3): Gershgorin bounds omega_max
// and gamma_max, and finalize() picks the fewest sub-steps T' = T / s with
// (omega_max^2 T'^2 + 2 gamma_max T') / 4 < 0.9; refused beyond 4096.
//
// Layout: axial coordinates (i, j) as in triangular_lattice.cpp: node (i, j) sits at
// x = (i + j/2) h, y = j (sqrt 3 / 2) h; its six neighbours are (i +- 1, j), (i, j +- 1),
// (i -+ 1, j +- 1). Cell (i, j) is at index j S + i of every array (stride S = width + 2: a halo
// cell on each side, a halo row above and below), so the neighbours sit at the fixed offsets +-1,
// +-S, +-(S - 1): no gather, no scatter. Empty cells (outside the body, fixed points, the halo)
// hold y = d = 0 and have zero coefficients, so they never move. Two loops, each over spans of
// consecutive cells (a row from its first node to its last; rows joined across gaps of up to 24
// empty cells):
//   lattice loop: nodes whose every neighbour that is a node is linked to them with the common
//     stiffness (all of a membrane built by build_membrane): c[p] (y[p+1] + y[p-1] + y[p+S] +
//     y[p-S] + y[p+S-1] + y[p-S+1]) - cd[p] y[p]; a free edge is an empty neighbour (y = 0, no c in
//     cd), a fixed edge an empty neighbour whose spring is an anchor in cd.
//   general loop: any other node, with three structure-of-arrays rows of link coefficients for
//     the forward directions, c_E[p] (p to p+1), c_N[p] (p to p+S), c_NW[p] (p to p+S-1), zero where
//     there is no link; p's backward links are c_E[p-1], c_N[p-S], c_NW[p-S+1].
// Vectorisation (g++ 12, -O3, the x86-64 baseline SSE2 the project builds with; checked with
// -fopt-info-vec-optimized): both loops vectorise, float and double ("loop vectorized using
// 16 byte vectors", 4 floats or 2 doubles a step, plus an 8-byte epilogue for float). The spans'
// bounds are data, the offsets S loop constants, the arrays __restrict: no runtime alias checks.
// (-march=x86-64-v3, AVX2 + FMA, measured 18 % faster on the 10 000-mass panel and 40 % on 55
// masses; not used, to keep one binary for every x86-64 and the same flags as the rest of ameoto.)
//
// Float or double (measured, docs/bench.md): GridMembrane is float. On the umbrella panel at
// 48 kHz float takes 0.54 to 0.64 of double's time (1 000 masses 1.1 us vs 2.0 us per sample;
// 10 000 masses 16 us vs 27 us, two sub-steps), and only float keeps 10 000 masses in real time on
// one core. Its cost in accuracy, float against double over 1 s of ringing with a drop every
// 0.1 s: largest error of the net force 2e-6 (55 masses), 8e-6 (1 000), 1.2e-4 (10 000) of its
// peak; RMS error against RMS signal 3e-5, 9e-5, 1.7e-3 (the stencil's y_j - y_i lose float's
// bits as the lattice gets finer: the Laplacian of a smooth field is (k h)^2 of it). On Faust's
// 52-mass triangle, 1.7e-4 of the peak after 0.1 s. BasicGridMembrane<double> is the accurate one.

#include <cstdint>
#include <vector>

#include "engine/core/stability.hpp"   // StabilityReport
#include "engine/core/triangular_lattice.hpp"

namespace ameoto {

struct AxialIndex {
    int i = 0, j = 0;
};

struct GridMembraneBody {
    double node_mass = 1.0;          // kg, every node
    double mass_damping = 0.0;       // alpha, 1/s: a damper alpha m from each mass to the ground
    double stiffness_damping = 0.0;  // beta, s: a damper beta k beside every spring
};

template <typename Real>
class BasicGridMembrane {
public:
    explicit BasicGridMembrane(const GridMembraneBody& body = {});

    int add_node(int i, int j);
    void add_link(int a, int b, double stiffness);
    void add_anchor(int a, double stiffness);
    void finalize(double time_step_s);

    void apply_force(int node, double newtons);
    double step();
    void reset();
    bool finite() const;

    int node_count() const { return static_cast<int>(node_i_.size()); }
    int link_count() const { return static_cast<int>(link_a_.size()); }
    double position(int node) const;           // m: y - (beta/T') d
    double velocity(int node) const;           // (x[n] - x[n-1]) / T' over the last sub-step
    const StabilityReport& stability() const { return stability_; }
    const GridMembraneBody& body() const { return body_; }
    int stride() const { return stride_; }     // S: cells per grid row
    int cell_count() const { return static_cast<int>(d_.size()); }
    int updated_cells() const;                 // cells the stencil visits per sub-step (nodes + gaps)
    int lattice_cells() const;                 // of which stepped by the lattice loop (one c per cell)

private:
    std::size_t cell(int node) const { return static_cast<std::size_t>(node_cell_[static_cast<std::size_t>(node)]); }
    double sub_step();

    GridMembraneBody body_;
    // build phase
    std::vector<int> node_i_, node_j_;
    std::vector<std::int32_t> link_a_, link_b_;
    std::vector<double> link_k_, anchor_k_;
    // grid (finalize): state and coefficients per cell, structure of arrays
    int stride_ = 0;
    std::vector<std::int32_t> node_cell_;
    std::vector<Real> d_, y_, y_next_;       // d = x[n] - x[n-1]; y = x + (beta/T') d (two buffers)
    std::vector<Real> c_e_, c_n_, c_nw_;     // forward links (general loop)
    std::vector<Real> c_lattice_;            // the common link coefficient on lattice cells (lattice loop)
    std::vector<Real> c_x_;                  // diagonal cd: links plus anchor
    double beta_over_dt_ = 0.0, alpha_dt_ = 0.0;
    double velocity_sum_ = 0.0;              // sum of d over the nodes (for the ground dampers' force)
    // cells [begin, end) visited by each loop
    std::vector<std::int32_t> general_begin_, general_end_, lattice_begin_, lattice_end_;
    std::vector<std::int32_t> anchor_cell_;          // anchored cells and their stiffness (N/m), for the net force
    std::vector<double> anchor_force_k_;
    // external forces: dense per cell, with the list of touched cells (capacity = nodes: no allocation)
    std::vector<double> external_;
    std::vector<unsigned char> listed_;
    std::vector<std::int32_t> touched_;
    std::size_t touched_count_ = 0;
    double force_scale_ = 0.0;   // T'^2 / m: external force to displacement
    StabilityReport stability_;
    double sub_dt_ = 0.0;
};

extern template class BasicGridMembrane<float>;
extern template class BasicGridMembrane<double>;

using GridMembrane = BasicGridMembrane<float>;

// The body build_membrane makes over `lattice` (models/membrane.hpp), on the grid: node mass
// s A (A = lattice.node_area), springs k = T / sqrt 3 to every neighbour and fixed point, Rayleigh
// damping alpha, beta. Node n of the result is node n of the lattice. Allocates.
template <typename Real = float>
BasicGridMembrane<Real> grid_membrane_over(const TriangularLattice& lattice, double areal_density, double tension,
                                           double alpha, double beta, double time_step_s);

// The axial coordinates (i, j) of a lattice's nodes, node 0 at (0, 0).
std::vector<AxialIndex> axial_coordinates(const TriangularLattice& lattice);

}  // namespace ameoto
