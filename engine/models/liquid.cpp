// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/liquid.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"

namespace ameoto {
namespace {

const std::array<Liquid, 3>& preset_table() {
    static const std::array<Liquid, 3> table{{
        {"water", constants::water_density, 7.49e-2, 1.52e-3},   // seed section 5.1.1
        {"milk", 1030.0, 5.2e-2, 2.0e-3},                       // Walstra et al. 2006; J. Dairy Res. 1983
        {"heavy_oil", 960.0, 3.2e-2, 380e-6 * 960.0},           // IFO 380 at 50 C (see the header)
    }};
    return table;
}

std::string out_of_range(const char* field, double value, double lo, double hi, const char* unit) {
    std::ostringstream os;
    os << field << " " << value << " " << unit << " is outside " << lo << ".." << hi << " " << unit;
    return os.str();
}

}  // namespace

namespace liquids {
const Liquid& water() { return preset_table()[0]; }
const Liquid& milk() { return preset_table()[1]; }
const Liquid& heavy_oil() { return preset_table()[2]; }
std::span<const Liquid> presets() { return preset_table(); }
}  // namespace liquids

std::optional<Liquid> find_liquid(std::string_view name) {
    for (const Liquid& l : preset_table())
        if (l.name == name) return l;
    return std::nullopt;
}

std::string validate(const Liquid& l) {
    using L = LiquidLimits;
    // !(in range) also rejects NaN.
    if (!(l.density >= L::density_min && l.density <= L::density_max))
        return out_of_range("density", l.density, L::density_min, L::density_max, "kg/m^3");
    if (!(l.surface_tension >= L::surface_tension_min && l.surface_tension <= L::surface_tension_max))
        return out_of_range("surface tension", l.surface_tension, L::surface_tension_min, L::surface_tension_max, "N/m");
    if (!(l.viscosity >= L::viscosity_min && l.viscosity <= L::viscosity_max))
        return out_of_range("viscosity", l.viscosity, L::viscosity_min, L::viscosity_max, "Pa s");
    return {};
}

Liquid make_liquid(std::string name, double density, double surface_tension, double viscosity) {
    Liquid l{std::move(name), density, surface_tension, viscosity};
    if (std::string why = validate(l); !why.empty()) throw std::invalid_argument("liquid '" + l.name + "': " + why);
    return l;
}

}  // namespace ameoto
