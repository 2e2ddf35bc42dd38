// SPDX-License-Identifier: GPL-3.0-or-later
// DropOnCanopy::turn_head (drop_on_canopy.hpp): the held umbrella heard by a turned head on the panned
// formats. The umbrella turns with the body (it is held), so only the head's own rotation H moves its
// panels: a panel whose centre lies at d from the head (body frame) is heard from H^T d, and panned by
// that direction's azimuth (the rings have no elevation: panning.hpp), which is how a pitch or a roll
// changes where an overhead panel is heard. In vacuum the Rayleigh path's panel sums are re-mixed; in
// air the dipole model's modal taps (each panel's own, mixed by the new gains).
#include <cmath>

#include "engine/models/ambisonics.hpp"
#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/panning.hpp"

namespace ameoto {

void DropOnCanopy::prepare_turn() {
    if (config_.output != SceneOutput::far_field || config_.channels < 2 || config_.listener != ListenerStyle::panned) return;
    const Vec3 head{0.0, 0.0, -config_.listener_below_m};
    panel_directions_.resize(static_cast<std::size_t>(canopy_.panel_count()));
    for (int k = 0; k < canopy_.panel_count(); ++k) {
        Vec3 centre{};
        for (int i = 0; i < canopy_.nodes_per_panel(); ++i) centre = centre + canopy_.rest_position(k, i);
        // The centre's distance out and height, at the panel's own azimuth (the layout's, panning.hpp): a
        // small turn moves the panel a little from where the unturned layout pans it, never a jump.
        const Vec3 d = centre / canopy_.nodes_per_panel() - head;
        const double out = std::hypot(d.x, d.y), az = canopy_.panel_azimuth(k);
        panel_directions_[static_cast<std::size_t>(k)] = Vec3{out * std::cos(az), out * std::sin(az), d.z};
    }
    turn_gains_.assign(static_cast<std::size_t>(config_.channels * canopy_.panel_count()), 0.0);
}

bool DropOnCanopy::turn_head(const std::array<double, 9>& h, int glide_frames) {
    if (panel_directions_.empty()) return false;
    const int panels = canopy_.panel_count(), channels = config_.channels;
    const bool identity = h == std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int k = 0; k < panels; ++k) {
        const Vec3 d = panel_directions_[static_cast<std::size_t>(k)];
        // H^T d (the columns of H are the head's axes): at rest, the layout's own azimuth, bit for bit.
        const double x = h[0] * d.x + h[3] * d.y + h[6] * d.z, y = h[1] * d.x + h[4] * d.y + h[7] * d.z;
        const auto g = pan_gains(identity ? canopy_.panel_azimuth(k) : std::atan2(y, x), channels);
        for (int c = 0; c < channels; ++c) turn_gains_[static_cast<std::size_t>(c * panels + k)] = g[static_cast<std::size_t>(c)];
    }
    if (!config_.air) {
        far_field_.set_panel_gains(turn_gains_.data(), glide_frames);
        return true;
    }
    // In air: the dipole model's taps re-mixed from each panel's own (dipole_radiation.hpp); at rest,
    // its own taps again, bit for bit.
    return identity ? dipole_.set_rest_gains(glide_frames) : dipole_.set_panel_gains(turn_gains_.data(), glide_frames);
}

}  // namespace ameoto
