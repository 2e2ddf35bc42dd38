// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The figures most test files share: the sample rate the engine tests run at and the physical constants
// they compare with. One definition, so that files built together (CMake's unity build, which CI uses to
// halve its compile time) cannot clash, and no file carries its own copy of pi.
//
// Interface (bring them in with `using namespace ameoto::test::common;`):
//   kFs    48 000 Hz, the rate the engine tests step at
//   kT     1 / kFs s, one step; kDt is the same step under the name some integrator tests use
//   kPi    engine/core/physical_constants.hpp's pi
//   kRho0  air's density, kg/m^3; kC  sound's speed in air, m/s (engine/core/physical_constants.hpp)

#include "engine/core/physical_constants.hpp"

namespace ameoto::test::common {

inline constexpr double kFs = 48000.0;
inline constexpr double kT = 1.0 / kFs;
inline constexpr double kDt = kT;
inline constexpr double kPi = ameoto::constants::pi;
inline constexpr double kRho0 = ameoto::constants::air_density;
inline constexpr double kC = ameoto::constants::speed_of_sound_air;

}  // namespace ameoto::test::common
