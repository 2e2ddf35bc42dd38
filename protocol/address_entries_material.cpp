// SPDX-License-Identifier: GPL-3.0-or-later
// The material rows of the OSC address table (address_entries.hpp): the drops' liquid and a surface's
// material, presets or custom ones defined (and stored under their names) over OSC.
#include "protocol/address_entries.hpp"

#include <algorithm>
#include <cctype>
#include <optional>

namespace ameoto::protocol::entries {
namespace {

// Names of custom liquids and materials: short, printable, no path characters (they may name files later).
std::optional<std::string> check_name(const std::string& name) {
    if (name.empty() || name.size() > 64) return "a name has 1 to 64 characters";
    for (const char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'))
            return "a name uses letters, digits, '-' and '_' only, not '" + std::string(1, c) + "'";
    return std::nullopt;
}

}  // namespace

void add_material_entries(std::vector<AddressSpec>& t) {
    t.push_back({"/material/liquid",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "water, milk, heavy_oil, or a custom liquid's name", "water"},
                  {"density", ArgumentKind::number, "kg/m^3", LiquidLimits::density_min, LiquidLimits::density_max, true,
                   "custom liquid: density"},
                  {"surface_tension", ArgumentKind::number, "N/m", LiquidLimits::surface_tension_min,
                   LiquidLimits::surface_tension_max, true, "custom liquid: surface tension"},
                  {"viscosity", ArgumentKind::number, "Pa s", LiquidLimits::viscosity_min, LiquidLimits::viscosity_max, true,
                   "custom liquid: dynamic viscosity"}},
                 "Make drops of a preset liquid, or define a custom one (stored under its name) and use it.",
                 "/done /material/liquid (once the drops use it)",
                 [](const ValidatedArguments& a, const ProtocolContext& ctx, Request& r) -> std::optional<std::string> {
                     const std::string& name = a.texts[0];
                     if (auto refusal = check_name(name)) return refusal;
                     if (a.numbers.empty()) {
                         std::optional<Liquid> liquid = find_liquid(name);
                         if (!liquid && ctx.custom_liquid) liquid = ctx.custom_liquid(name);
                         if (!liquid) return "no liquid named '" + name + "' (presets: water, milk, heavy_oil)";
                         r.liquid = *liquid;
                     } else if (a.numbers.size() != 3) {
                         return "a custom liquid needs all three of density (kg/m^3), surface tension (N/m) and viscosity (Pa s)";
                     } else {
                         if (find_liquid(name)) return "'" + name + "' is a preset; give the custom liquid another name";
                         Liquid liquid{name, a.numbers[0], a.numbers[1], a.numbers[2]};
                         if (const std::string why = validate(liquid); !why.empty()) return why;
                         r.liquid = liquid;
                     }
                     r.action = Action::set_liquid;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/material/liquid.reply s name, f density (kg/m^3), f surface_tension (N/m), f viscosity (Pa s)"};
    t.push_back({"/material/surface",
                 {{"surface", ArgumentKind::text, "", 0, 0, false, "a surface of the scene (umbrella)", "umbrella"},
                  {"material", ArgumentKind::text, "", 0, 0, false, "nylon, seed-nylon, vinyl, or a custom material's name", "nylon"},
                  {"areal_density", ArgumentKind::number, "kg/m^2", 1e-3, 100.0, true, "custom material: mass per area"},
                  {"tension", ArgumentKind::number, "N/m", 0.1, 1e10, true, "custom material: membrane tension"},
                  {"mass_damping", ArgumentKind::number, "1/s", 0.0, 1e4, true, "custom material: Rayleigh alpha"},
                  {"stiffness_damping", ArgumentKind::number, "s", 0.0, 1e-3, true, "custom material: Rayleigh beta"}},
                 "Make a surface of a preset material, or define a custom one (stored under its name) and use it. "
                 "A material the surface's integrator cannot run stably is refused with the bound.",
                 "/done /material/surface (once the surface rings in it)",
                 [](const ValidatedArguments& a, const ProtocolContext& ctx, Request& r) -> std::optional<std::string> {
                     const std::string& surface = a.texts[0];
                     const std::string& name = a.texts[1];
                     if (std::find(ctx.surfaces.begin(), ctx.surfaces.end(), surface) == ctx.surfaces.end())
                         return "no surface named '" + surface + "'";
                     if (auto refusal = check_name(name)) return refusal;
                     // The umbrella's material is written into saved scenes, whose names are 1-32 characters.
                     if (!is_scene_name(name)) return "a material name has 1 to 32 characters";
                     if (a.numbers.empty()) {
                         std::optional<MembraneMaterial> material = membrane_material(name);
                         if (!material && ctx.custom_material) material = ctx.custom_material(name);
                         if (!material) return "no material named '" + name + "' (presets: nylon, seed-nylon, vinyl)";
                         r.material = *material;
                     } else if (a.numbers.size() != 4) {
                         return "a custom material needs all four of areal density (kg/m^2), tension (N/m), mass damping (1/s) "
                                "and stiffness damping (s)";
                     } else {
                         if (membrane_material(name)) return "'" + name + "' is a preset; give the custom material another name";
                         MembraneMaterial m = MembraneMaterial::custom(name, a.numbers[0], a.numbers[1], a.numbers[2], a.numbers[3]);
                         if (const MaterialCheck check = validate_membrane_material(m); !check.ok) return check.reason;
                         r.material = m;
                     }
                     r.surface = surface;
                     r.action = Action::set_surface_material;
                     return std::nullopt;
                 }});
    t.back().query = {true,
                      {{"surface", ArgumentKind::text, "", 0, 0, false, "a surface of the scene", "umbrella"}},
                      "/material/surface.reply s surface, s material, f areal_density (kg/m^2), f tension (N/m), f mass_damping (1/s), "
                      "f stiffness_damping (s)"};
}

}  // namespace ameoto::protocol::entries
