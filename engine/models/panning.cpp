// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/panning.hpp"

#include <cmath>

#include "engine/core/physical_constants.hpp"

namespace ameoto {

std::array<double, max_pan_channels> pan_gains(double azimuth, int channels) {
    std::array<double, max_pan_channels> g{};
    if (channels <= 1) {
        g[0] = 1.0;
        return g;
    }
    if (channels == 2) {
        // pan 0 = hard left (azimuth +90 deg), 1 = hard right.
        const double pan = 0.5 * (1.0 - std::sin(azimuth));
        g[0] = std::cos(pan * constants::pi / 2.0);
        g[1] = std::sin(pan * constants::pi / 2.0);
        return g;
    }
    // Speaker c sits at azimuth a_c = first - c * spacing (clockwise from front-left).
    const double spacing = 2.0 * constants::pi / channels;
    const double first = spacing / 2.0;
    double rel = (first - azimuth) / spacing;   // position in speaker units, clockwise
    rel -= std::floor(rel / channels) * channels;
    const int c0 = static_cast<int>(rel) % channels;
    const int c1 = (c0 + 1) % channels;
    const double t = rel - std::floor(rel);
    g[static_cast<std::size_t>(c0)] = std::cos(t * constants::pi / 2.0);
    g[static_cast<std::size_t>(c1)] = std::sin(t * constants::pi / 2.0);
    return g;
}

}  // namespace ameoto
