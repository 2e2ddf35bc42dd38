// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/scene_record.hpp"

#include <algorithm>

#include "protocol/receive.hpp"

namespace ameoto {

// A change must leave a scene that can still be saved and rebuilt (e.g. /listener must not carry the
// umbrella out of range).
std::string SceneRecord::refusal(const Command& c) const { return validate_scene(protocol::scene_after(scene_, c)); }

void SceneRecord::apply(const Command& c) {
    if (c.kind == CommandKind::orientation) orientation_ = {c.values[0], c.values[1], c.values[2]};
    scene_ = protocol::scene_after(scene_, c);
}

// Timed changes whose frame has played, in the order of their frames (ties: as sent).
void SceneRecord::apply_due(std::uint64_t frame) {
    if (timed_settings_.empty()) return;
    std::stable_sort(timed_settings_.begin(), timed_settings_.end(), [](const Command& a, const Command& b) { return a.frame < b.frame; });
    auto due = timed_settings_.begin();
    while (due != timed_settings_.end() && due->frame <= frame) apply(*due++);
    timed_settings_.erase(timed_settings_.begin(), due);
}

// Only once it is in effect (a refused material changed nothing): the umbrella's record names it too.
void SceneRecord::material_changed(const MembraneMaterial& material) {
    for (SurfaceDescription& f : scene_.surfaces)
        if (f.kind == SurfaceKind::umbrella) f.material = material.name;
    material_ = material;
}

}  // namespace ameoto
