// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Air drag coefficients for Body3D masses that stand for water drops (engine/core/body3d.hpp).
//
// Interface:
//   drag::seed_linear_drag                     // 1.77e-8 kg/s: the seed's -c v per mass (section 5.1.1)
//   double drag::beard_terminal_speed(D);      // m/s, Beard (1976), still air at 20 C and 1013 hPa
//   double drag::drop_drag_coefficient(D);     // C_d of a drop of diameter D (m) at its terminal speed
//   double drag::drop_quadratic_drag(D);       // b = rho_air C_d (pi D^2 / 4) / 2 (kg/m), for
//                                              // Body3D::set_quadratic_drag: F = -b |v| v
//
// What C_d is. A rigid sphere's C_d is a function of the Reynolds number alone, but a falling drop
// above about 1 mm flattens, and its drag rises above the sphere's: no sphere fit gives Gunn & Kinzer's
// speeds. Beard (1976, J. Atmos. Sci. 33:851) fitted the drag of drops in three regimes:
//   D < 19 um:          Stokes with slip correction, v = (rho_w - rho_a) g D^2 C_sc / (18 eta);
//   19 um <= D < 1.07 mm: ln Re = C_sc-corrected polynomial (b0..b6) in X = ln N_Da, the Davies (Best)
//                       number N_Da = C_d Re^2 = 4 rho_a (rho_w - rho_a) g D^3 / (3 eta^2): a C_d(Re)
//                       relation for near-spherical drops, solved at the force balance;
//   1.07 mm <= D < 7 mm: Re = N_P^(1/6) exp(polynomial (b0..b5) in X = ln(Bo N_P^(1/6))), with the Bond
//                       number Bo = 4 (rho_w - rho_a) g D^2 / (3 sigma) and the physical property
//                       number N_P = sigma^3 rho_a^2 / (eta^4 (rho_w - rho_a) g): the flattening.
// This is physics, not a fit to the table we test against: it gives Gunn & Kinzer's speeds within
// 2.2 % from 0.3 to 5.8 mm (the test measures each point). C_d then follows from the force balance
// at terminal speed, m g = buoyancy + drag:  C_d = 4 (rho_w - rho_a) g D / (3 rho_a v_t^2).
// Body3D holds C_d constant per mass, at its value at the drop's terminal speed: the speed reached is
// exact, while the approach from rest is slightly off (at lower speed a real drop's C_d is higher),
// which rain never shows because drops arrive at terminal speed. Body3D leaves out buoyancy
// (rho_a / rho_w = 0.12 % of the weight), so a simulated drop falls 0.06 % faster than Beard's speed.
// Above 7 mm (drops break up in air) the speed and C_d of a 7 mm drop are used; the area stays real.
//
// Seed preset: the seed's linear drag, c = 1.77e-8 kg/s per mass, gives a 1 mm drop (one mass of
// rho pi (1 mm)^3 / 6 = 5.2e-7 kg) a terminal speed m g / c = 290 m/s against the real 4.03 m/s
// (physics.md section 1). Kept as a preset for the seed's sound; use quadratic drag for realism.

namespace ameoto::drag {

constexpr double seed_linear_drag = 1.77e-8;          // kg/s (seed section 5.1.1, "air drag coefficient")
constexpr double air_viscosity = 1.818e-5;            // Pa s, dry air at 20 C (Beard 1976)
constexpr double air_mean_free_path = 6.62e-8;        // m at 20 C, 1013 hPa (Beard 1976), for slip
constexpr double water_surface_tension = 0.0728;      // N/m at 20 C (physics.md section 4)

double beard_terminal_speed(double diameter_m);
double drop_drag_coefficient(double diameter_m);
double drop_quadratic_drag(double diameter_m);

}  // namespace ameoto::drag
