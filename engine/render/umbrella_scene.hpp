#pragma once
// What the renderer swaps as one piece when a material or liquid changes: the umbrella scene with its
// lattice drops (the full level of detail) and the impact templates recorded from them (the template
// level of detail, for the rain), both for the same material, liquid, geometry and sample rate.
//
// Interface:
//   UmbrellaScene scene(drop_on_canopy_config);   // off the audio thread: builds the scene (~1 s the
//                                                 // first time in a process: the drop lattices), then
//                                                 // records the templates from it (~0.5 s)
//   scene.drops        // DropOnCanopy: canopy, drop pool, collider, far field
//   scene.templates    // ImpactTemplateTable (impact_templates.hpp)

#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/impact_templates.hpp"

namespace ameoto {

struct UmbrellaScene {
    explicit UmbrellaScene(const DropOnCanopyConfig& config)
        : drops(config), templates(record_impact_templates(config)) {}
    DropOnCanopy drops;
    ImpactTemplateTable templates;
};

}  // namespace ameoto
