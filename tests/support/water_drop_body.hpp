// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// For Body3D tests: a 5 mm water drop as a bare Body3D (122 masses, 537 cohesive links, with the
// calibration engine/models/drop.hpp gives water: bond k 0.09976 N/m, damping 6.327e-6 N s/m, break
// force 1.074e-4 N, core 0.9 h at 144.5 N/m; quadratic drag 6.36e-8 kg/m per mass), its lowest masses
// just above z = 0, every mass moving at `velocity`.
//
// Interface:
//   ameoto::test::add_five_mm_water_drop(body, Vec3{0.3, 0.0, -9.09});   // then gravity, integrator, finalize

#include <cstddef>

#include "engine/core/body3d.hpp"
#include "engine/core/lattice_ball.hpp"

namespace ameoto::test {

inline void add_five_mm_water_drop(Body3D& body, Vec3 velocity) {
    const auto shape = lattice_ball_shape(125);
    const double d = 5e-3, h = d * shape.spacing;
    for (const Vec3& p : shape.position) {
        const int m = body.add_mass(5.354e-7, Vec3{0.0, 0.0, 0.5 * d} + d * p);
        body.set_velocity(m, velocity);
        body.set_quadratic_drag(m, 6.36e-8);
    }
    for (int l = 0; l < shape.link_count(); ++l)
        body.add_cohesive(shape.link_a[static_cast<std::size_t>(l)], shape.link_b[static_cast<std::size_t>(l)], 0.09976, 6.327e-6, h,
                          1.074e-4, 0.9 * h, 144.5);
}

}  // namespace ameoto::test
