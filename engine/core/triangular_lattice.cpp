// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/triangular_lattice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

namespace ameoto {
namespace {

// Signed distance of p from edge i, positive inside a counter-clockwise polygon.
double inside_distance(const std::vector<PolygonEdge>& poly, std::size_t i, Point2 p) {
    const Point2 a = poly[i].start;
    const Point2 b = poly[(i + 1) % poly.size()].start;
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len = std::hypot(ex, ey);
    return (ex * (p.y - a.y) - ey * (p.x - a.x)) / len;
}

// nearest_node's index (TriangularLattice::NodeGrid) over the axial bounding box of the nodes.
void fill_grid(TriangularLattice& lattice, const std::map<std::pair<int, int>, int>& index, double x0, double y0,
               double row, double extent) {
    using Grid = TriangularLattice::NodeGrid;
    auto& g = lattice.grid;
    g.x0 = x0;
    g.y0 = y0;
    g.inverse_spacing = 1.0 / lattice.spacing;
    g.inverse_row = 1.0 / row;
    g.node_count = lattice.nodes.size();
    if (index.empty()) return;
    int i_lo = index.begin()->first.first, i_hi = i_lo, j_lo = index.begin()->first.second, j_hi = j_lo;
    for (const auto& [key, node] : index) {
        i_lo = std::min(i_lo, key.first);
        i_hi = std::max(i_hi, key.first);
        j_lo = std::min(j_lo, key.second);
        j_hi = std::max(j_hi, key.second);
    }
    g.i0 = i_lo - Grid::pad;
    g.j0 = j_lo - Grid::pad;
    g.width = i_hi - i_lo + 1 + 2 * Grid::pad;
    g.height = j_hi - j_lo + 1 + 2 * Grid::pad;
    const double far = std::numeric_limits<double>::infinity();
    g.cells.assign(static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height), Grid::Cell{{far, far}, -1});
    for (const auto& [key, node] : index)
        g.cells[static_cast<std::size_t>(key.second - g.j0) * static_cast<std::size_t>(g.width) +
                static_cast<std::size_t>(key.first - g.i0)] = {lattice.nodes[static_cast<std::size_t>(node)], node};
    // Rounding margin (see nearest_node): the query lies within a few cells of the grid, so every
    // coordinate involved is below `extent` plus a few spacings; positions, axial coordinates and
    // distances are each off by a few ulps of that. 64 of them is ample and costs nothing (a query
    // that close to the acceptance radius only moves on to the next block).
    const double slack =
        64.0 * std::numeric_limits<double>::epsilon() * (extent + 2.0 * Grid::pad * lattice.spacing);
    for (int k = 1; k <= 2; ++k) {
        const double radius = std::max(0.0, k * row - slack);
        g.accept2[k] = radius * radius;
    }
}

// Squared distance, the one formula both nearest_node paths use, so they round alike.
double distance2(Point2 a, Point2 p) {
    const double dx = a.x - p.x, dy = a.y - p.y;
    return dx * dx + dy * dy;
}

}  // namespace

double polygon_area(const std::vector<PolygonEdge>& polygon) {
    double twice = 0.0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Point2 a = polygon[i].start, b = polygon[(i + 1) % polygon.size()].start;
        twice += a.x * b.y - b.x * a.y;
    }
    return 0.5 * twice;
}

bool polygon_contains(const std::vector<PolygonEdge>& polygon, Point2 p) {
    for (std::size_t i = 0; i < polygon.size(); ++i)
        if (inside_distance(polygon, i, p) < 0.0) return false;
    return true;
}

int TriangularLattice::nearest_node_brute_force(Point2 p) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const double d2 = distance2(nodes[i], p);
        if (d2 < best_d2) {
            best_d2 = d2;
            best = static_cast<int>(i);
        }
    }
    return best;
}

// The same answer as the brute force, from the few sites around p.
// With v = (y - y0) / row - 1/2 and u = (x - x0) / h - 1/2 (the layout inverted: a site (i, j) has
// v = j and u - j/2 = i), take the block of 2k rows j = floor(v) - k + 1 .. floor(v) + k and, in each,
// the 2k sites i = floor(u - j/2) - k + 1 .. floor(u - j/2) + k. Every site outside the block is at
// least k rows (|j - v| >= k, so |dy| >= k row) or k spacings along its row (|dx| >= k h > k row) from
// p. So if the nearest node inside the block is closer than k row, no node outside can beat or tie it,
// and the brute force's answer (the least squared distance, lowest index on a tie) is the block's.
// The block is read row by row upwards and left to right, which is the order of the node indices
// (build_triangular_lattice numbers the nodes that way), so a strict < with the same distance2 keeps
// the lowest index on a tie, as the brute force does; empty sites sit at infinity and never win.
// k = 1 (4 sites) answers wherever its nearest site is a node (the whole interior) or a node within a row;
// k = 2 (16 sites) most of the rest near the boundary; otherwise (p far outside, or in a narrow corner)
// the brute force does.
// Rounding (p's axial coordinates, the stored positions, the squared distances) is absorbed by accept2,
// which build_triangular_lattice sets a margin (far above the few ulps involved) inside (k row)^2.
// p must lie within a few cells of the nodes (the grid's padding): that refuses NaN and infinities
// too, and keeps every cell index in range, so the lookup needs no bounds checks.
namespace {

template <int k>
int nearest_in_block(const TriangularLattice::NodeGrid& g, Point2 p, int r, double cu, double& best_d2) {
    int best = -1;
    best_d2 = std::numeric_limits<double>::infinity();
    for (int rr = r - k + 1; rr <= r + k; ++rr) {
        const int c = static_cast<int>(cu - 0.5 * rr);   // floor: positive here
        const TriangularLattice::NodeGrid::Cell* cell =
            g.cells.data() + static_cast<std::size_t>(rr) * static_cast<std::size_t>(g.width) + static_cast<std::size_t>(c);
        for (int dc = 1 - k; dc <= k; ++dc) {
            const double d2 = distance2(cell[dc].at, p);
            const bool closer = d2 < best_d2;
            best_d2 = closer ? d2 : best_d2;
            best = closer ? cell[dc].node : best;
        }
    }
    return best;
}

}  // namespace

int TriangularLattice::nearest_node(Point2 p) const {
    const NodeGrid& g = grid;
    if (g.cells.empty() || g.node_count != nodes.size()) return nearest_node_brute_force(p);
    // Cell (r, c) is the site j = j0 + r, i = i0 + c: p's fractional row is rf = v - j0, and in cell
    // row r its fractional column is u - j/2 - i0 = cu - r/2.
    const double rf = ((p.y - g.y0) * g.inverse_row - 0.5) - g.j0;
    const double cu = ((p.x - g.x0) * g.inverse_spacing - 0.5) - g.i0 - 0.5 * g.j0;
    const double cm = cu - 0.5 * rf;   // the fractional column in p's own row
    // Blocks up to k = 2 span rows floor(rf) - 1 .. floor(rf) + 2 and, in those, columns within 1 of
    // cm, then 1 and 2 more: inside the grid when rf is in [2, height - 3) and cm in [3, width - 4).
    if (!(rf >= 2.0 && rf < g.height - 3.0 && cm >= 3.0 && cm < g.width - 4.0)) return nearest_node_brute_force(p);
    const int r = static_cast<int>(rf);   // floor: positive here
    double d2 = 0.0;
    int best = nearest_in_block<1>(g, p, r, cu, d2);
    if (best >= 0 && d2 < g.accept2[1]) return best;
    best = nearest_in_block<2>(g, p, r, cu, d2);
    if (best >= 0 && d2 < g.accept2[2]) return best;
    return nearest_node_brute_force(p);
}

TriangularLattice build_triangular_lattice(const std::vector<PolygonEdge>& polygon, double spacing) {
    if (polygon.size() < 3) throw std::invalid_argument("lattice polygon needs at least 3 vertices");
    if (!(polygon_area(polygon) > 0.0)) throw std::invalid_argument("lattice polygon must be counter-clockwise");
    if (!(spacing > 0.0)) throw std::invalid_argument("lattice spacing must be positive");

    double x_min = polygon[0].start.x, x_max = x_min, y_min = polygon[0].start.y, y_max = y_min;
    for (const auto& e : polygon) {
        x_min = std::min(x_min, e.start.x);
        x_max = std::max(x_max, e.start.x);
        y_min = std::min(y_min, e.start.y);
        y_max = std::max(y_max, e.start.y);
    }
    const double row = spacing * std::sqrt(3.0) / 2.0;
    // Axial coordinates (i, j): x = x_min + (i + j/2 + 1/2) h, y = y_min + (j + 1/2) row.
    auto position = [&](int i, int j) {
        return Point2{x_min + (i + 0.5 * j + 0.5) * spacing, y_min + (j + 0.5) * row};
    };
    const int j_max = static_cast<int>(std::ceil((y_max - y_min) / row)) + 1;
    const int span = static_cast<int>(std::ceil((x_max - x_min) / spacing)) + 2;

    TriangularLattice lattice;
    lattice.spacing = spacing;
    lattice.node_area = spacing * row;
    std::map<std::pair<int, int>, int> index;
    for (int j = -1; j <= j_max; ++j) {
        for (int i = -span - j_max; i <= span + j_max; ++i) {
            const Point2 p = position(i, j);
            if (polygon_contains(polygon, p)) {
                index[{i, j}] = static_cast<int>(lattice.nodes.size());
                lattice.nodes.push_back(p);
            }
        }
    }
    lattice.anchor_links.assign(lattice.nodes.size(), 0);
    fill_grid(lattice, index, x_min, y_min, row, std::max({std::fabs(x_min), std::fabs(x_max), std::fabs(y_min), std::fabs(y_max)}));
    // Three of the six neighbour directions, so each pair is met once; outside neighbours are
    // checked in all six directions for anchors.
    const int directions[6][2] = {{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}};
    for (const auto& [key, node] : index) {
        for (int d = 0; d < 6; ++d) {
            const std::pair<int, int> other{key.first + directions[d][0], key.second + directions[d][1]};
            const auto found = index.find(other);
            if (found != index.end()) {
                if (d < 3) lattice.links.push_back({node, found->second});
                continue;
            }
            // Outside: a fixed point if it lies beyond any fixed edge.
            const Point2 p = position(other.first, other.second);
            for (std::size_t e = 0; e < polygon.size(); ++e) {
                if (polygon[e].fixed && inside_distance(polygon, e, p) < 0.0) {
                    ++lattice.anchor_links[static_cast<std::size_t>(node)];
                    break;
                }
            }
        }
    }
    return lattice;
}

double spacing_for_node_count(const std::vector<PolygonEdge>& polygon, int target_nodes) {
    if (target_nodes < 1) throw std::invalid_argument("node count must be at least 1");
    // Start from area / (node area) and search nearby spacings for the closest count: the count is
    // a step function of the spacing, so the closed form alone can miss by a row.
    const double guess = std::sqrt(polygon_area(polygon) / (target_nodes * std::sqrt(3.0) / 2.0));
    double best = guess;
    int best_error = std::numeric_limits<int>::max();
    for (int k = -40; k <= 40; ++k) {
        const double h = guess * (1.0 + 0.005 * k);
        const int error = std::abs(static_cast<int>(build_triangular_lattice(polygon, h).nodes.size()) - target_nodes);
        if (error < best_error) {
            best_error = error;
            best = h;
        }
    }
    return best;
}

}  // namespace ameoto
