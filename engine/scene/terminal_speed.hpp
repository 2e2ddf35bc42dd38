// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Terminal fall speed of water drops in still air at sea level.
//
// Interface:
//   double terminal_speed(double diameter_m);     // m/s, from the Gunn & Kinzer (1949) table
//   std::span<const TerminalSpeedPoint> gunn_kinzer_table();   // the table itself (mm, m/s)
//
// Source: Gunn & Kinzer 1949, J. Meteor. 6:243, Table 2, as in ../shared/reference/gunn_kinzer_1949.csv
// (a test checks this copy against that file). Between points: linear interpolation. Below the
// first point (0.078 mm): Stokes' law, v proportional to D^2, which the table itself follows there.
// Above 5.8 mm the table ends because larger drops break up in air; the speed stays at 9.17 m/s.

#include <span>

namespace ameoto {

struct TerminalSpeedPoint {
    double diameter_mm;
    double speed_m_per_s;
};

std::span<const TerminalSpeedPoint> gunn_kinzer_table();

// diameter in m (SI); returns m/s.
double terminal_speed(double diameter_m);

}  // namespace ameoto
