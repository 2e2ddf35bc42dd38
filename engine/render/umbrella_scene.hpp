// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the renderer swaps as one piece when a material or liquid changes: the umbrella scene with its
// lattice drops (the full level of detail), the impact templates recorded from them (the template level
// of detail) and the texture grains' calibration from those (the texture level), all for the same
// material, liquid, geometry and sample rate.
//
// Interface:
//   UmbrellaScene scene(drop_on_canopy_config);   // off the audio thread: builds the scene (~1 s the
//                                                 // first time in a process: the drop lattices), then
//                                                 // records the templates from it (~0.5 s) and
//                                                 // calibrates the texture (~0.2 s)
//   scene.drops        // DropOnCanopy: canopy, drop pool, collider, far field
//   scene.templates    // ImpactTemplateTable (impact_templates.hpp)
//   scene.texture      // TextureCalibration (texture_grains.hpp)

#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/impact_templates.hpp"
#include "engine/models/texture_grains.hpp"

namespace ameoto {

struct UmbrellaScene {
    explicit UmbrellaScene(const DropOnCanopyConfig& config)
        : drops(config), templates(record_impact_templates(config)), texture(calibrate_texture(config, templates)) {}
    DropOnCanopy drops;
    ImpactTemplateTable templates;
    TextureCalibration texture;
};

}  // namespace ameoto
