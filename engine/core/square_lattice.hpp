// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A 2-D square lattice (4 neighbours) over a rectangle whose edges are each fixed or free.
//
// Interface:
//   SquareLattice lat = build_square_lattice(lx_m, ly_m, spacing_m, RectangleEdges{...});
//   lat.nodes, lat.links, lat.anchor_links, lat.node_area (= h^2), lat.nx, lat.ny
//   lat.length_x, lat.length_y        // the rectangle the lattice models (see below)
//   lat.index(i, j)                   // node at column i, row j
//   lat.nearest_node(p)
//
// Membrane on it: the 5-point Laplacian lap(u) ~ sum_j (u_j - u_i) / h^2, so T A lap(u) with A = h^2 is a
// spring of stiffness k = T to each of the 4 neighbours, and a node's mass is s h^2 (Bilbao, Numerical
// Sound Synthesis, 2009, ch. 11: the 5-point scheme; physics.md section 3). Its modes are
// omega^2 = (4 c^2 / h^2)(sin^2(kx h / 2) + sin^2(ky h / 2)), c^2 = T / s (physics.md section 4).
// Boundary placement, chosen so that formula holds exactly with the rectangle's own wavenumbers:
//   fixed edge: the fixed points (anchors) lie ON the edge, one spacing beyond the outermost nodes:
//     along x with both edges fixed, nodes at x = h, 2h, ..., nx h and Lx = (nx + 1) h; the 1-D Dirichlet
//     chain has eigenvalues 4 sin^2(m pi / (2 (nx + 1))), i.e. kx = m pi / Lx exactly;
//   free edge: the edge lies half a spacing beyond the outermost nodes (where their cells end; the
//     outer node simply has no neighbour there): with one edge fixed and one free, L = (n + 1/2) h and
//     the chain's eigenvalues are 4 sin^2((m - 1/2) pi / (2 n + 1)), i.e. k = (m - 1/2) pi / L exactly
//     (the n - 1/2 of the continuum's free edge);
//   both free: L = n h (k = (m - 1) pi / L).
// The node counts are the nearest integers to those relations for the given L and h; length_x/y report
// the rectangle actually modelled (equal to lx, ly when they fit).

#include <vector>

#include "engine/core/triangular_lattice.hpp"   // Point2, LatticeLink

namespace ameoto {

struct RectangleEdges {
    bool left = true, right = true, bottom = true, top = true;   // true: fixed
};

struct SquareLattice {
    double spacing = 0.0;
    double node_area = 0.0;
    int nx = 0, ny = 0;
    double length_x = 0.0, length_y = 0.0;
    std::vector<Point2> nodes;           // node (i, j) at index(i, j); the rectangle's corner at (0, 0)
    std::vector<LatticeLink> links;      // each neighbouring pair once
    std::vector<int> anchor_links;       // per node, how many of its 4 neighbours are fixed points
    int index(int i, int j) const { return j * nx + i; }
    int nearest_node(Point2 p) const;
};

// Throws std::invalid_argument unless lx, ly, spacing are positive and each side holds at least 1 node.
SquareLattice build_square_lattice(double lx, double ly, double spacing, RectangleEdges edges);

}  // namespace ameoto
