// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A 3-D vector for the build-phase and query interfaces of Body3D (engine/core/body3d.hpp).
//
// Interface:
//   Vec3 p{x, y, z};   p + q, p - q, s * p, p / s, dot(p, q), norm(p)
//
// Only at the boundary: Body3D itself stores x, y and z in separate arrays (structure of arrays), so
// its step loops stay simple and vectorisable; this struct carries one mass's values in and out.

#include <cmath>

namespace ameoto {

struct Vec3 {
    double x = 0.0, y = 0.0, z = 0.0;
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
constexpr Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

}  // namespace ameoto
