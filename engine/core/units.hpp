// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Unit conversions at the engine's boundary. Everything inside the engine is SI
// (m, s, kg, N, Pa); these helpers name the conversions so call sites read as physics.

namespace ameoto::units {

constexpr double mm_to_m(double mm) { return mm * 1e-3; }
constexpr double m_to_mm(double m) { return m * 1e3; }
// Rain rate: 1 mm/h of water depth = 1e-3 m / 3600 s.
constexpr double mm_per_h_to_m_per_s(double r) { return r * (1e-3 / 3600.0); }
constexpr double m_per_s_to_mm_per_h(double r) { return r * (3600.0 / 1e-3); }
constexpr double deg_to_rad(double d) { return d * (3.14159265358979323846 / 180.0); }

}  // namespace ameoto::units
