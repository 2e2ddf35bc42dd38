#include "engine/core/triangular_lattice.hpp"

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

int TriangularLattice::nearest_node(Point2 p) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const double dx = nodes[i].x - p.x, dy = nodes[i].y - p.y;
        const double d2 = dx * dx + dy * dy;
        if (d2 < best_d2) {
            best_d2 = d2;
            best = static_cast<int>(i);
        }
    }
    return best;
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
