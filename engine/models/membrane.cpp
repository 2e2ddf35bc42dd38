#include "engine/models/membrane.hpp"

#include <cmath>

namespace ameoto {

double MembraneMaterial::wave_speed() const { return std::sqrt(tension / areal_density); }

MembraneMaterial MembraneMaterial::nylon_canopy() {
    return MembraneMaterial{"nylon", 0.06, 1000.0, 20.0, 2e-6};
}

Membrane build_membrane(const std::vector<PolygonEdge>& polygon, int target_masses,
                        const MembraneMaterial& material, double time_step_s) {
    Membrane membrane;
    membrane.material = material;
    membrane.lattice = build_triangular_lattice(polygon, spacing_for_node_count(polygon, target_masses));
    const auto& lattice = membrane.lattice;
    const double node_mass = material.areal_density * lattice.node_area;
    const double k = material.tension / std::sqrt(3.0);   // see header: T A lap(u) on the 6-neighbour lattice
    const double z = material.stiffness_damping * k;
    auto& net = membrane.network;
    for (std::size_t i = 0; i < lattice.nodes.size(); ++i) {
        const int m = net.add_mass(node_mass, material.mass_damping * node_mass);
        if (lattice.anchor_links[i] > 0) net.add_anchor(m, k * lattice.anchor_links[i], z * lattice.anchor_links[i]);
    }
    for (const auto& link : lattice.links) net.add_link(link.a, link.b, k, z);
    net.finalize(time_step_s);
    return membrane;
}

}  // namespace ameoto
