#include "engine/models/membrane.hpp"

#include <cmath>

namespace ameoto {

double MembraneMaterial::wave_speed() const { return std::sqrt(tension / areal_density); }

MembraneMaterial MembraneMaterial::nylon_canopy() {
    return MembraneMaterial{"nylon", 0.06, 1000.0, 20.0, 2e-6};
}

MembraneMaterial MembraneMaterial::seed_nylon() {
    MembraneMaterial m;
    m.name = "seed-nylon";
    const double k = 1.2e9, panel_mass = 0.12;
    const double panel_area = 0.5 * 0.5 * std::sin(2.0 * 3.14159265358979323846 / 8.0) / 2.0;   // canopy.hpp
    m.areal_density = panel_mass / panel_area;
    m.tension = std::sqrt(3.0) * k;
    m.mass_damping = 0.0;
    m.stiffness_damping = 0.231 / k;
    m.link_stiffness = k;
    m.total_mass = panel_mass;
    m.link_damping = 0.231;
    return m;
}

Membrane build_membrane(const std::vector<PolygonEdge>& polygon, int target_masses,
                        const MembraneMaterial& material, double time_step_s, const NetworkOptions& options) {
    Membrane membrane;
    membrane.material = material;
    membrane.lattice = build_triangular_lattice(polygon, spacing_for_node_count(polygon, target_masses));
    const auto& lattice = membrane.lattice;
    const double node_mass = material.total_mass > 0.0 ? material.total_mass / static_cast<double>(lattice.nodes.size())
                                                        : material.areal_density * lattice.node_area;
    // See header: T A lap(u) on the 6-neighbour lattice, unless the link stiffness is given.
    const double k = material.link_stiffness > 0.0 ? material.link_stiffness : material.tension / std::sqrt(3.0);
    const double z = material.link_damping > 0.0 ? material.link_damping : material.stiffness_damping * k;
    auto& net = membrane.network;
    for (std::size_t i = 0; i < lattice.nodes.size(); ++i) {
        const int m = net.add_mass(node_mass, material.mass_damping * node_mass);
        if (lattice.anchor_links[i] > 0) net.add_anchor(m, k * lattice.anchor_links[i], z * lattice.anchor_links[i]);
    }
    for (const auto& link : lattice.links) net.add_link(link.a, link.b, k, z);
    net.finalize(time_step_s, options);
    return membrane;
}

}  // namespace ameoto
