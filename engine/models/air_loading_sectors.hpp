// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Internal to the air's mass on the umbrella (air_loading.cpp, air_loading_helmholtz.cpp): one panel's
// triangle cut into nearly square sub-cells, each a uniform doublet (a vortex ring), and the coarser level
// of the same cells that Richardson's extrapolation pairs it with. Build phase only (allocates).
//
// Interface:
//   std::vector<SectorCell> c = sector_cells(canopy, rows);   // panel 0's sub-cells, rows from the shaft
//   single_elements(c), grouped_elements(c, nodes)            // the finer and the coarser level
//   ring_velocity(p, corners, cos, sin)                       // Biot-Savart at p of a unit ring, turned
//   ring_velocities(canopy, c, elements)                      // [d]: every element's at every other's
//   turned_quad(cell, cos, sin), integrate_quad(q, gauss3, f) // a sub-cell turned to panel d, and the
//   for_each_quad_point(q, gauss2, visit)                     // Gauss-Legendre tensor rule on it

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/triangular_lattice.hpp"

namespace ameoto {

class Canopy;

namespace air_sectors {

// A sub-cell of one panel's sampling: its polygon (counter-clockwise), centroid, area and node.
struct SectorCell {
    std::vector<Point2> corners;
    Point2 centroid;
    double area = 0.0;
    int node = -1;
    int row = 0;        // i below
    double v = 0.0;     // the cell's middle across the row, 0..1
};

// A unit of uniform doublet strength: one cell, or a group of cells (the coarse level, below) whose
// ring is the sum of its cells' rings (their shared edges cancel), collocated at its centroid.
struct SectorElement {
    std::vector<std::size_t> cells;
    Point2 centroid;
    double area = 0.0;
    int node = -1;
};

// Panel 0's triangle (the shaft O and the rib tips A, B) cut into rows parallel to the hem, row i
// (0..rows-1) between u = i / rows and (i + 1) / rows of the way from O to the hem, and row i into i + 1
// equal parts along the hem's direction: P(u, v) = u (A + v (B - A)). The cells are nearly square, all
// of one size (the apex's is a triangle); rows do not share corners (hanging corners are harmless:
// every cell is its own ring). Each cell belongs to the node Canopy::locate gives at its centroid.
std::vector<SectorCell> sector_cells(const Canopy& canopy, int rows);

// The Biot-Savart velocity of a unit ring at p (ring_segment_velocity summed, with sqrt for hypot: the
// sampling never meets its overflow range).
double ring_velocity(Point2 p, const std::vector<Point2>& ring, double cos_turn, double sin_turn);

// Every cell an element of its own (the finer level).
std::vector<SectorElement> single_elements(const std::vector<SectorCell>& cells);

// The coarser level of the same cells (rows even): the cells of rows 2I and 2I + 1 that fall in part J
// of I + 1 across the row (the sampling at rows / 2) and belong to one node form one element. Its
// nodes' regions are the finer level's exactly, so the two levels differ only in the doublets' size
// (sampling each level's regions afresh moves a node's share by up to a cell, not smoothly in h, which
// made the extrapolation indefinite).
std::vector<SectorElement> grouped_elements(const std::vector<SectorCell>& cells, int nodes);

// The Biot-Savart velocities of a level's unit rings (Laplace's kernel), one matrix per panel offset d:
// g_d(i, k), the velocity at panel 0's element i from panel d's element k (panel d is panel 0 turned by
// 2 pi d / N, its elements numbered alike).
std::vector<Eigen::MatrixXd> ring_velocities(const Canopy& canopy, const std::vector<SectorCell>& cells,
                                             const std::vector<SectorElement>& elements);

// Quadrature on the sub-cells (the Helmholtz kernel's terms: air_loading_helmholtz.cpp,
// air_loading_in_phase.cpp).

// Gauss-Legendre on [0, 1].
struct Rule {
    std::vector<double> x, w;
};
inline const Rule gauss2{{0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)}, {0.5, 0.5}};
inline const Rule gauss3{{0.5 - 0.5 * std::sqrt(0.6), 0.5, 0.5 + 0.5 * std::sqrt(0.6)}, {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0}};

// A sub-cell turned by (ct, st): its corners as a bilinear quadrilateral (a triangle repeats a corner).
struct Quad {
    Point2 c[4];
    std::vector<Point2> polygon;
    Point2 centroid;
    double size = 0.0;   // sqrt(area)
};

inline Quad turned_quad(const SectorCell& cell, double ct, double st) {
    Quad q;
    auto turn = [&](Point2 p) { return Point2{ct * p.x - st * p.y, st * p.x + ct * p.y}; };
    for (const Point2& p : cell.corners) q.polygon.push_back(turn(p));
    for (int i = 0; i < 4; ++i) q.c[i] = q.polygon[static_cast<std::size_t>(std::min<int>(i, static_cast<int>(q.polygon.size()) - 1))];
    if (q.polygon.size() == 3) q.c[3] = q.polygon[0];
    q.centroid = turn(cell.centroid);
    q.size = std::sqrt(cell.area);
    return q;
}

// Each of the rule's points on the quad, visit(y, weight): the tensor product on the bilinear map, the
// weight carrying the map's Jacobian (sum weight = the quad's area).
template <class V>
void for_each_quad_point(const Quad& q, const Rule& rule, V&& visit) {
    for (std::size_t i = 0; i < rule.x.size(); ++i) {
        for (std::size_t j = 0; j < rule.x.size(); ++j) {
            const double s = rule.x[i], t = rule.x[j];
            const double w00 = (1 - s) * (1 - t), w10 = s * (1 - t), w11 = s * t, w01 = (1 - s) * t;
            const Point2 y{w00 * q.c[0].x + w10 * q.c[1].x + w11 * q.c[2].x + w01 * q.c[3].x,
                           w00 * q.c[0].y + w10 * q.c[1].y + w11 * q.c[2].y + w01 * q.c[3].y};
            // Jacobian of P(s, t).
            const double xs = (1 - t) * (q.c[1].x - q.c[0].x) + t * (q.c[2].x - q.c[3].x);
            const double ys = (1 - t) * (q.c[1].y - q.c[0].y) + t * (q.c[2].y - q.c[3].y);
            const double xt = (1 - s) * (q.c[3].x - q.c[0].x) + s * (q.c[2].x - q.c[1].x);
            const double yt = (1 - s) * (q.c[3].y - q.c[0].y) + s * (q.c[2].y - q.c[1].y);
            visit(y, rule.w[i] * rule.w[j] * std::abs(xs * yt - ys * xt));
        }
    }
}

// integral over the quad of f(y) dA by the rule.
template <class F>
auto integrate_quad(const Quad& q, const Rule& rule, F&& f) {
    decltype(f(Point2{})) sum{};
    for_each_quad_point(q, rule, [&](Point2 y, double weight) { sum += weight * f(y); });
    return sum;
}

}  // namespace air_sectors
}  // namespace ameoto
