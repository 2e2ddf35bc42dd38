// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_mesh.hpp"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "engine/core/grid_membrane.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/core/triangular_lattice.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/membrane.hpp"

namespace ameoto::client {

BenchMesh canopy_panel_mesh(int target_masses) {
    // The canopy's panel (engine/models/canopy.cpp): hem free, the two ribs fixed.
    const CanopyGeometry g;
    const double half_angle = constants::pi / g.panels;
    const double half_width = g.radius_m * std::sin(half_angle), height = g.radius_m * std::cos(half_angle);
    const std::vector<PolygonEdge> outline = {{{-half_width, 0.0}, false}, {{half_width, 0.0}, true}, {{0.0, height}, true}};
    const TriangularLattice lattice = build_triangular_lattice(outline, spacing_for_node_count(outline, target_masses));
    const MembraneMaterial nylon = MembraneMaterial::nylon_canopy();

    BenchMesh mesh;
    mesh.name = "canopy panel";
    // As build_membrane: node mass s A, k = T / sqrt 3, anchors k per fixed neighbour.
    mesh.node_mass = nylon.areal_density * lattice.node_area;
    mesh.alpha = nylon.mass_damping;
    mesh.beta = nylon.stiffness_damping;
    mesh.time_step = 1.0 / bench_sample_rate;
    const double k = nylon.tension / std::sqrt(3.0);
    for (const AxialIndex& a : axial_coordinates(lattice)) mesh.nodes.push_back({a.i, a.j});
    for (const LatticeLink& l : lattice.links) mesh.links.push_back({l.a, l.b, k});
    for (std::size_t n = 0; n < lattice.nodes.size(); ++n)
        if (lattice.anchor_links[n] > 0) mesh.anchors.push_back({static_cast<int>(n), -1, k * lattice.anchor_links[n]});
    // A drop near the middle of the panel; the listener hears the net force (no listening node).
    mesh.excite_node = lattice.nearest_node({0.0, height / 3.0});
    mesh.listen_node = mesh.excite_node;
    return mesh;
}

bool MiTriangle::fixed(int i, int j) {
    return (i == 0 && j == 0) || (i == side - 1 && j == 0) || (i == 0 && j == side - 1);
}

int MiTriangle::faust_index(int i, int j) {
    // Rows of side, side - 1, ... points, listed row after row.
    int index = 0;
    for (int r = 0; r < j; ++r) index += side - r;
    return index + i;
}

BenchMesh mi_triangle_mesh() {
    using T = MiTriangle;
    BenchMesh mesh;
    mesh.name = "mi-faust triangleMesh";
    mesh.node_mass = T::mass;
    mesh.alpha = T::air_friction / T::mass;   // oscil's z = alpha m
    mesh.beta = T::damping / T::stiffness;    // springDamper's Z = beta K
    mesh.time_step = 1.0;                     // mi.lib's parameters are per sample
    std::map<std::pair<int, int>, int> node;  // (i, j) -> node; fixed corners absent
    for (int j = 0; j < T::side; ++j) {
        for (int i = 0; i + j < T::side; ++i) {
            if (T::fixed(i, j)) continue;
            node[{i, j}] = static_cast<int>(mesh.nodes.size());
            mesh.nodes.push_back({i, j});
        }
    }
    // The .dsp's three families of springs, in its order; a spring to a corner is an anchor.
    auto spring = [&](int i1, int j1, int i2, int j2) {
        const bool f1 = T::fixed(i1, j1), f2 = T::fixed(i2, j2);
        if (f1 && f2) throw std::logic_error("mi triangle: spring between two fixed points");
        if (f1) mesh.anchors.push_back({node.at({i2, j2}), -1, T::stiffness});
        else if (f2) mesh.anchors.push_back({node.at({i1, j1}), -1, T::stiffness});
        else mesh.links.push_back({node.at({i1, j1}), node.at({i2, j2}), T::stiffness});
    };
    for (int j = 0; j < T::side; ++j)
        for (int i = 0; i + 1 + j < T::side; ++i) spring(i, j, i + 1, j);
    for (int j = 0; j + 1 < T::side; ++j)
        for (int i = 0; i + j + 1 < T::side; ++i) spring(i, j, i, j + 1);
    for (int j = 0; j + 1 < T::side; ++j)
        for (int i = 0; i + j + 1 < T::side; ++i) spring(i + 1, j, i, j + 1);
    mesh.excite_node = node.at({T::pluck_i, T::pluck_j});
    mesh.listen_node = node.at({T::listen_i, T::listen_j});
    return mesh;
}

}  // namespace ameoto::client
