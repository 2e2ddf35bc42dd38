// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Physical constants used across the engine (SI). Sources in ../shared/reference/physics.md.

namespace ameoto::constants {

constexpr double pi = 3.14159265358979323846;
constexpr double gravity = 9.80665;             // m/s^2, standard gravity
constexpr double water_density = 998.0;         // kg/m^3 at 20 C
constexpr double air_density = 1.204;           // kg/m^3 at 20 C, sea level
constexpr double speed_of_sound_air = 343.0;    // m/s at 20 C

}  // namespace ameoto::constants
