// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The liquid a drop is made of: density, surface tension, viscosity (seed section 6: water, milk,
// heavy oil, or any custom values).
//
// Interface:
//   Liquid water = liquids::water();                  // also liquids::milk(), liquids::heavy_oil()
//   std::span<const Liquid> all = liquids::presets();
//   std::optional<Liquid> l = find_liquid("milk");    // a preset by name (exact, lower case)
//   std::string why = validate(liquid);               // "" if usable, else names the field and range
//   Liquid custom = make_liquid("syrup", 1300, 0.07, 5.0);   // validates; throws std::invalid_argument
//   liquid.kinematic_viscosity();                     // nu = mu / rho, m^2/s
//
// Presets (SI, about 20 C unless said):
//   water      998 kg/m^3, 7.49e-2 N/m, 1.52e-3 Pa s. Surface tension and viscosity are the seed's
//              (section 5.1.1; they match water at about 5-10 C); density as constants::water_density.
//   milk       1030 kg/m^3, 5.2e-2 N/m, 2.0e-3 Pa s: whole milk at 20 C. Density and viscosity:
//              Walstra, Wouters & Geurts, Dairy Science and Technology (2006), ch. 4 (1027-1033 kg/m^3;
//              about 2 mPa s); surface tension from the fit gamma = 1.8e-4 T^2 - 0.163 T + 55.6 mN/m
//              (T in C) for whole and skim milk, J. Dairy Res. 50:259 (1983), at 20 C: 52.4 mN/m.
//   heavy_oil  960 kg/m^3, 3.2e-2 N/m, 0.3648 Pa s: heavy fuel oil (the seed's 重油) of grade IFO 380
//              (ISO 8217 RMG 380: 380 mm^2/s at 50 C, its reference temperature) at 50 C, where its
//              density is about 960 kg/m^3 (at most 991 at 15 C, less when warm): mu = 380e-6 * 960.
//              Surface tension: typical of residual petroleum oils, 0.030-0.035 N/m (an estimate, not a
//              measured value for this grade). At 20 C the same oil is about 6 times more viscous.
//
// Validation ranges (wide enough for any real liquid, narrow enough to catch unit mistakes such as
// g/cm^3 or mN/m): density 100..20000 kg/m^3, surface tension 1e-4..1 N/m, viscosity 1e-6..1e3 Pa s.

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace ameoto {

struct Liquid {
    std::string name;
    double density = 0.0;           // kg/m^3
    double surface_tension = 0.0;   // N/m
    double viscosity = 0.0;         // Pa s (dynamic)
    double kinematic_viscosity() const { return viscosity / density; }   // m^2/s
    bool operator==(const Liquid&) const = default;
};

struct LiquidLimits {
    static constexpr double density_min = 100.0, density_max = 20000.0;
    static constexpr double surface_tension_min = 1e-4, surface_tension_max = 1.0;
    static constexpr double viscosity_min = 1e-6, viscosity_max = 1e3;
};

namespace liquids {
const Liquid& water();
const Liquid& milk();
const Liquid& heavy_oil();
std::span<const Liquid> presets();
}  // namespace liquids

std::optional<Liquid> find_liquid(std::string_view name);
std::string validate(const Liquid& liquid);
Liquid make_liquid(std::string name, double density, double surface_tension, double viscosity);

}  // namespace ameoto
