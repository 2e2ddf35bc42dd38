// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/scene/terminal_speed.hpp"

#include <array>

namespace ameoto {
namespace {

constexpr std::array<TerminalSpeedPoint, 35> kGunnKinzer{{
    {0.078, 0.18}, {0.1, 0.27}, {0.2, 0.72}, {0.3, 1.17}, {0.4, 1.62}, {0.5, 2.06}, {0.6, 2.47},
    {0.7, 2.87},   {0.8, 3.27}, {0.9, 3.67}, {1.0, 4.03}, {1.2, 4.64}, {1.4, 5.17}, {1.6, 5.65},
    {1.8, 6.09},   {2.0, 6.49}, {2.2, 6.90}, {2.4, 7.27}, {2.6, 7.57}, {2.8, 7.82}, {3.0, 8.06},
    {3.2, 8.26},   {3.4, 8.44}, {3.6, 8.60}, {3.8, 8.72}, {4.0, 8.83}, {4.2, 8.92}, {4.4, 8.98},
    {4.6, 9.03},   {4.8, 9.07}, {5.0, 9.09}, {5.2, 9.12}, {5.4, 9.14}, {5.6, 9.16}, {5.8, 9.17},
}};

}  // namespace

std::span<const TerminalSpeedPoint> gunn_kinzer_table() { return kGunnKinzer; }

double terminal_speed(double diameter_m) {
    const double d_mm = diameter_m * 1e3;
    if (d_mm <= 0.0) return 0.0;
    const auto& first = kGunnKinzer.front();
    if (d_mm <= first.diameter_mm) {
        // Stokes regime: v = v0 (D / D0)^2.
        const double ratio = d_mm / first.diameter_mm;
        return first.speed_m_per_s * ratio * ratio;
    }
    if (d_mm >= kGunnKinzer.back().diameter_mm) return kGunnKinzer.back().speed_m_per_s;
    // The table is short: a linear scan is cheaper than a binary search at this size.
    std::size_t i = 1;
    while (kGunnKinzer[i].diameter_mm < d_mm) ++i;
    const auto& lo = kGunnKinzer[i - 1];
    const auto& hi = kGunnKinzer[i];
    const double t = (d_mm - lo.diameter_mm) / (hi.diameter_mm - lo.diameter_mm);
    return lo.speed_m_per_s + t * (hi.speed_m_per_s - lo.speed_m_per_s);
}

}  // namespace ameoto
