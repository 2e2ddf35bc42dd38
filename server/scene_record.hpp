// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The scene as it plays now, on the control thread's side: what the queries answer (/rain/rate,
// /surface/set NAME, /material/liquid ...) and what /scene/save writes. It follows the engine: an
// untimed change from when the audio thread takes it, a timed one once its frame has played, a
// rebuilt scene, material or liquid once the audio thread has it.
//
// Interface:
//   SceneRecord record(scene, liquid, material);
//   record.scene()  record.liquid()  record.material()   // material: the umbrella's, when there is one
//   record.orientation()                         // the head's yaw, pitch, roll (rad): not part of the
//                                                // scene (never saved), kept across scene loads as the
//                                                // renderer keeps it
//   std::string why = record.refusal(command);   // "" when the scene after it is still valid
//   record.apply(command);                       // rain, wind, listener, lod: in effect from now
//   record.apply_at_frame(command);              // timed: waits (at most 4096) for apply_due(frame)
//   record.apply_due(frame);                     // each poll: the timed changes whose frame has played
//   record.loaded(scene, material);              // a whole scene swapped in (timed changes stay waiting)
//   record.material_changed(m);  record.liquid_changed(l);
//
// Thread: the control thread only.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/render/command.hpp"
#include "engine/scene/scene_description.hpp"
#include "engine/models/liquid.hpp"
#include "engine/models/membrane.hpp"

namespace ameoto {

class SceneRecord {
public:
    static constexpr std::size_t max_timed_settings = 4096;

    SceneRecord(SceneDescription scene, Liquid liquid, MembraneMaterial material)
        : scene_(std::move(scene)), liquid_(std::move(liquid)), material_(std::move(material)) {}

    const SceneDescription& scene() const { return scene_; }
    const Liquid& liquid() const { return liquid_; }
    const MembraneMaterial& material() const { return material_; }
    const std::array<double, 3>& orientation() const { return orientation_; }

    std::string refusal(const Command& c) const;
    void apply(const Command& c);
    void apply_at_frame(const Command& c) {
        if (timed_settings_.size() < max_timed_settings) timed_settings_.push_back(c);
    }
    void apply_due(std::uint64_t frame);
    void loaded(const SceneDescription& scene, const MembraneMaterial& material) {
        scene_ = scene;
        material_ = material;
    }
    void material_changed(const MembraneMaterial& material);
    void liquid_changed(const Liquid& liquid) { liquid_ = liquid; }

private:
    SceneDescription scene_;
    Liquid liquid_;
    MembraneMaterial material_;
    std::array<double, 3> orientation_{};   // /listener/orientation: yaw, pitch, roll, rad
    std::vector<Command> timed_settings_;   // rain, wind, listener, lod changes waiting for their frame
};

}  // namespace ameoto
