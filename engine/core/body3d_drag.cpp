// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/body3d_drag.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"

namespace ameoto::drag {
namespace {

constexpr double kRegime2 = 19e-6;     // m: Beard's regime boundaries
constexpr double kRegime3 = 1.07e-3;
constexpr double kLargest = 7e-3;

// Horner evaluation of sum c[i] x^i.
template <std::size_t N>
double polynomial(const double (&c)[N], double x) {
    double y = c[N - 1];
    for (std::size_t i = N - 1; i-- > 0;) y = y * x + c[i];
    return y;
}

}  // namespace

double beard_terminal_speed(double diameter_m) {
    if (!(diameter_m > 0.0)) throw std::invalid_argument("drop diameter must be positive");
    const double d = std::min(diameter_m, kLargest);
    const double rho_a = constants::air_density, eta = air_viscosity, g = constants::gravity;
    const double delta_rho = constants::water_density - rho_a;
    const double slip = 1.0 + 2.51 * air_mean_free_path / d;   // Cunningham slip correction
    if (d < kRegime2) return delta_rho * g * d * d * slip / (18.0 * eta);
    if (d < kRegime3) {
        // Beard (1976) regime 2: Reynolds number from the Davies number.
        static constexpr double b[] = {-0.318657e1, 0.992696,     -0.153193e-2, -0.987059e-3,
                                       -0.578878e-3, 0.855176e-4, -0.327815e-5};
        const double davies = 4.0 * rho_a * delta_rho * g * d * d * d / (3.0 * eta * eta);
        const double reynolds = slip * std::exp(polynomial(b, std::log(davies)));
        return eta * reynolds / (rho_a * d);
    }
    // Beard (1976) regime 3: Reynolds number from the Bond and physical property numbers.
    static constexpr double b[] = {-0.500015e1, 0.523778e1, -0.204914e1, 0.475294, -0.542819e-1, 0.238449e-2};
    const double sigma = water_surface_tension;
    const double bond = 4.0 * delta_rho * g * d * d / (3.0 * sigma);
    const double np6 = std::pow(sigma * sigma * sigma * rho_a * rho_a / (eta * eta * eta * eta * delta_rho * g), 1.0 / 6.0);
    const double reynolds = np6 * std::exp(polynomial(b, std::log(bond * np6)));
    return eta * reynolds / (rho_a * d);
}

double drop_drag_coefficient(double diameter_m) {
    const double d = std::min(diameter_m, kLargest);
    const double v = beard_terminal_speed(d);
    const double delta_rho = constants::water_density - constants::air_density;
    // Force balance at terminal speed: (pi/6) D^3 delta_rho g = (1/2) rho_a C_d (pi/4) D^2 v^2.
    return 4.0 * delta_rho * constants::gravity * d / (3.0 * constants::air_density * v * v);
}

double drop_quadratic_drag(double diameter_m) {
    // b uses the drop's real diameter, C_d its (capped) value: above 7 mm the drag area keeps growing.
    const double area = constants::pi * diameter_m * diameter_m / 4.0;
    return 0.5 * constants::air_density * drop_drag_coefficient(diameter_m) * area;
}

}  // namespace ameoto::drag
