// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/square_lattice.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {
namespace {

// Nodes along one side and the offset of the first node from the low edge (header: fixed edges one
// spacing beyond the outer nodes, free edges half a spacing).
struct Axis {
    int count;
    double first;    // position of node 0
    double length;   // modelled length
};

Axis axis(double length, double h, bool low_fixed, bool high_fixed) {
    const double low = low_fixed ? 1.0 : 0.5, high = high_fixed ? 1.0 : 0.5;
    // length = (count - 1 + low + high) h
    const int count = static_cast<int>(std::lround(length / h - low - high + 1.0));
    if (count < 1) throw std::invalid_argument("square lattice: a side holds no node at this spacing");
    return {count, low * h, (count - 1 + low + high) * h};
}

}  // namespace

int SquareLattice::nearest_node(Point2 p) const {
    const int i = std::clamp(static_cast<int>(std::lround((p.x - nodes.front().x) / spacing)), 0, nx - 1);
    const int j = std::clamp(static_cast<int>(std::lround((p.y - nodes.front().y) / spacing)), 0, ny - 1);
    return index(i, j);
}

SquareLattice build_square_lattice(double lx, double ly, double spacing, RectangleEdges edges) {
    if (!(lx > 0.0) || !(ly > 0.0) || !(spacing > 0.0)) throw std::invalid_argument("square lattice: sizes must be positive");
    const Axis ax = axis(lx, spacing, edges.left, edges.right);
    const Axis ay = axis(ly, spacing, edges.bottom, edges.top);
    SquareLattice lat;
    lat.spacing = spacing;
    lat.node_area = spacing * spacing;
    lat.nx = ax.count;
    lat.ny = ay.count;
    lat.length_x = ax.length;
    lat.length_y = ay.length;
    const auto n = static_cast<std::size_t>(lat.nx) * static_cast<std::size_t>(lat.ny);
    lat.nodes.reserve(n);
    lat.anchor_links.assign(n, 0);
    for (int j = 0; j < lat.ny; ++j)
        for (int i = 0; i < lat.nx; ++i) lat.nodes.push_back({ax.first + i * spacing, ay.first + j * spacing});
    for (int j = 0; j < lat.ny; ++j) {
        for (int i = 0; i < lat.nx; ++i) {
            const int node = lat.index(i, j);
            if (i + 1 < lat.nx) lat.links.push_back({node, lat.index(i + 1, j)});
            if (j + 1 < lat.ny) lat.links.push_back({node, lat.index(i, j + 1)});
            int& anchors = lat.anchor_links[static_cast<std::size_t>(node)];
            anchors += (i == 0 && edges.left) + (i == lat.nx - 1 && edges.right);
            anchors += (j == 0 && edges.bottom) + (j == lat.ny - 1 && edges.top);
        }
    }
    return lat;
}

}  // namespace ameoto
