// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A 2-D triangular lattice over a convex polygon whose edges are each fixed or free.
//
// Interface:
//   std::vector<PolygonEdge> edges = {{{x0,y0}, fixed}, {{x1,y1}, free}, ...};  // CCW vertices; the
//                                         // flag belongs to the edge from this vertex to the next
//   TriangularLattice lat = build_triangular_lattice(edges, spacing_m);
//   lat.nodes            // node centres inside the polygon (m)
//   lat.links            // pairs of neighbouring nodes (each pair once)
//   lat.anchor_links     // for each node, how many of its 6 neighbours are fixed points
//   lat.node_area        // m^2 that each node stands for: (sqrt 3 / 2) h^2
//   lat.nearest_node(p)  // index of the node nearest p (lowest index on a tie), -1 if none; O(1), no
//                        // allocation; exactly nearest_node_brute_force(p), which tries every node
//   spacing_for_node_count(edges, n)   // the spacing whose lattice has about n nodes
//
// Why triangular: its dispersion is the most isotropic of the 2-D meshes (seed section 4.2, Fig. 7;
// Savioja & Valimaki 2000). Rows run along x from the polygon's lowest y, the first row half a row
// inside, so a free edge along the bottom (an umbrella's hem) lies half way between the last row and
// the next, where a node's area ends. A neighbour outside the polygon across a fixed edge becomes a
// fixed point (anchor); across a free edge it is simply absent (a free boundary).

#include <cstddef>
#include <vector>

namespace ameoto {

struct Point2 {
    double x = 0.0, y = 0.0;
};

struct PolygonEdge {
    Point2 start;        // vertex; the edge runs from here to the next vertex (counter-clockwise)
    bool fixed = true;
};

struct LatticeLink {
    int a = 0, b = 0;
};

struct TriangularLattice {
    double spacing = 0.0;
    double node_area = 0.0;
    std::vector<Point2> nodes;
    std::vector<LatticeLink> links;
    std::vector<int> anchor_links;

    int nearest_node(Point2 p) const;               // O(1) through `grid` below; no allocation
    int nearest_node_brute_force(Point2 p) const;   // every node: the definition (and the fallback)

    // Node index by axial coordinates (i, j), filled by build_triangular_lattice. Cell (r, c) stands for
    // the site i = i0 + c, j = j0 + r, at x = x0 + (i + j/2 + 1/2) h, y = y0 + (j + 1/2) row: its node
    // and that node's position (a copy of nodes[node]), or node -1 and an infinite position where the
    // site is outside the polygon. The cells cover the nodes' axial bounding box plus a border of
    // `pad` empty cells on every side, so nearest_node reads its candidates without bounds checks.
    // nearest_node uses it while it covers `nodes` (node_count equal to nodes.size()); a lattice
    // assembled by hand, or whose nodes were added to afterwards, falls back to the brute force. Moving
    // existing nodes would make it wrong: build a new lattice instead.
    struct NodeGrid {
        static constexpr int pad = 4;
        struct Cell {
            Point2 at;
            int node = -1;
        };
        double x0 = 0.0, y0 = 0.0;                   // the build's origin (the polygon's x_min, y_min)
        double inverse_spacing = 0.0, inverse_row = 0.0;
        int i0 = 0, j0 = 0, width = 0, height = 0;   // cell (0, 0)'s axial coordinates; cells per row, rows
        std::vector<Cell> cells;                     // row-major
        std::size_t node_count = 0;
        double accept2[3] = {0.0, 0.0, 0.0};   // [k]: a block-k candidate this close (squared) is the answer
    } grid;
};

double polygon_area(const std::vector<PolygonEdge>& polygon);
bool polygon_contains(const std::vector<PolygonEdge>& polygon, Point2 p);

TriangularLattice build_triangular_lattice(const std::vector<PolygonEdge>& polygon, double spacing);
double spacing_for_node_count(const std::vector<PolygonEdge>& polygon, int target_nodes);

}  // namespace ameoto
