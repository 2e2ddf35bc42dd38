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
//   spacing_for_node_count(edges, n)   // the spacing whose lattice has about n nodes
//
// Why triangular: its dispersion is the most isotropic of the 2-D meshes (seed section 4.2, Fig. 7;
// Savioja & Valimaki 2000). Rows run along x from the polygon's lowest y, the first row half a row
// inside, so a free edge along the bottom (an umbrella's hem) lies half way between the last row and
// the next, where a node's area ends. A neighbour outside the polygon across a fixed edge becomes a
// fixed point (anchor); across a free edge it is simply absent (a free boundary).

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
    int nearest_node(Point2 p) const;   // brute force: lattices here are small; no allocation
};

double polygon_area(const std::vector<PolygonEdge>& polygon);
bool polygon_contains(const std::vector<PolygonEdge>& polygon, Point2 p);

TriangularLattice build_triangular_lattice(const std::vector<PolygonEdge>& polygon, double spacing);
double spacing_for_node_count(const std::vector<PolygonEdge>& polygon, int target_nodes);

}  // namespace ameoto
