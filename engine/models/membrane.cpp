// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/membrane.hpp"

#include <cmath>
#include <cstdio>

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

MembraneMaterial MembraneMaterial::vinyl() {
    // 0.15 mm x 1330 kg/m^3 = 0.1995 kg/m^2. Rayleigh damping matched to eta = 0.1 at 50 Hz and 2 kHz:
    // alpha = 2 eta w1 w2 / (w1 + w2) = 61, beta = 2 eta / (w1 + w2) = 1.55e-5 (rounded).
    return MembraneMaterial{"vinyl", 0.20, 200.0, 60.0, 1.6e-5};
}

MembraneMaterial MembraneMaterial::custom(std::string name, double areal_density, double tension, double alpha,
                                          double beta) {
    return MembraneMaterial{std::move(name), areal_density, tension, alpha, beta};
}

const std::vector<std::string>& membrane_material_names() {
    static const std::vector<std::string> names{"nylon", "seed-nylon", "vinyl"};
    return names;
}

std::optional<MembraneMaterial> membrane_material(std::string_view name) {
    if (name == "nylon") return MembraneMaterial::nylon_canopy();
    if (name == "seed-nylon") return MembraneMaterial::seed_nylon();
    if (name == "vinyl" || name == "pvc") return MembraneMaterial::vinyl();
    return std::nullopt;
}

namespace {

// "" when lo <= value <= hi, else a sentence naming the value, the range and why (below or above it).
std::string membrane_out_of_range(const char* what, double value, double lo, double hi, const char* unit, const char* why_low,
                         const char* why_high) {
    if (std::isfinite(value) && value >= lo && value <= hi) return {};
    const char* why = !std::isfinite(value) ? "it must be a finite number" : (value < lo ? why_low : why_high);
    char buffer[320];
    std::snprintf(buffer, sizeof buffer, "%s %g %s is outside %g .. %g %s: %s", what, value, unit, lo, hi, unit, why);
    return buffer;
}

// Optional overrides: 0 means "not given"; otherwise the range applies.
std::string optional_out_of_range(const char* what, double value, double lo, double hi, const char* unit,
                                  const char* why_low, const char* why_high) {
    if (value == 0.0) return {};
    return membrane_out_of_range(what, value, lo, hi, unit, why_low, why_high);
}

constexpr const char* negative_damping = "negative damping feeds energy in (it diverges under any integrator)";

}  // namespace

MaterialCheck validate_membrane_material(const MembraneMaterial& m) {
    const std::string reasons[] = {
        m.name.empty() ? std::string("a material needs a name") : std::string(),
        membrane_out_of_range("areal density", m.areal_density, 1e-3, 100.0, "kg/m^2",
                     "lighter than any film that could hold a drop (cling film is about 0.01)",
                     "heavier than 1 cm of steel: a plate, not a membrane (its bending stiffness is not modelled)"),
        membrane_out_of_range("tension", m.tension, 0.1, 1e10, "N/m",
                     "a membrane that slack sags under its own weight instead of being held taut",
                     "no sheet holds that (the seed's 1.2e9 N/m links are 2.1e9 N/m)"),
        membrane_out_of_range("mass damping alpha", m.mass_damping, 0.0, 1e4, "1/s", negative_damping,
                     "every mode below 800 Hz would be overdamped (alpha / 2 > w): the membrane no longer rings"),
        membrane_out_of_range("stiffness damping beta", m.stiffness_damping, 0.0, 1e-3, "s", negative_damping,
                     "every mode above 320 Hz would be overdamped (beta w^2 / 2 > w)"),
        optional_out_of_range("link stiffness", m.link_stiffness, 1e-3, 1e10, "N/m",
                              "0 means tension / sqrt 3; a given link must be a positive spring",
                              "no sheet holds that"),
        optional_out_of_range("total mass", m.total_mass, 1e-6, 100.0, "kg",
                              "0 means areal density times area; a given panel mass must be positive",
                              "heavier than any umbrella panel could be"),
        optional_out_of_range("link damping", m.link_damping, 1e-9, 1e3, "N s/m",
                              "0 means beta times the link stiffness; a given damper must be positive",
                              "every mode would be overdamped"),
    };
    MaterialCheck check;
    for (const auto& r : reasons) {
        if (r.empty()) continue;
        check.ok = false;
        check.reason += (check.reason.empty() ? "" : "; ") + r;
    }
    if (!check.ok) check.reason = "material '" + m.name + "': " + check.reason;
    return check;
}

MaterialCheck check_membrane_material(const std::vector<PolygonEdge>& polygon, int target_masses,
                                      const MembraneMaterial& material, double time_step_s,
                                      const NetworkOptions& options) {
    MaterialCheck check = validate_membrane_material(material);
    if (!check.ok) return check;
    try {
        const Membrane m = build_membrane(polygon, target_masses, material, time_step_s, options);
        check.stability = m.network.stability();
    } catch (const StabilityError& e) {
        check.ok = false;
        check.reason = "material '" + material.name + "' cannot run here: " + e.what();
    } catch (const std::exception& e) {
        check.ok = false;
        check.reason = "material '" + material.name + "': " + e.what();
    }
    return check;
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
