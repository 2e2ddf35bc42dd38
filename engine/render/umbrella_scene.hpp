// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the renderer swaps as one piece when a material or liquid changes: the umbrella scene with its
// lattice drops (the full level of detail), the impact templates recorded from them (the template level
// of detail) and the texture grains' calibration from those (the texture level), all for the same
// material, liquid, geometry and sample rate.
//
// Interface:
//   UmbrellaScene scene(drop_on_canopy_config);   // off the audio thread: builds one canopy (in air
//                                                 // its modes, ~0.6 s) and the scene on a copy, then
//                                                 // records the templates from copies (~0.5 s) and
//                                                 // calibrates the texture (~0.2 s)
//   UmbrellaScene scene(config, prototype);       // the same from the caller's canopy, never stepped
//   scene.drops        // DropOnCanopy: canopy, drop pool, collider, far field
//   scene.templates    // ImpactTemplateTable (impact_templates.hpp)
//   scene.texture      // TextureCalibration (texture_grains.hpp)

#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/impact_templates.hpp"
#include "engine/models/texture_grains.hpp"

namespace ameoto {

struct UmbrellaScene {
    // One canopy is built (its lattice, and in air its air-loaded modes, ~0.6 s: the costliest part of a
    // scene in air) and copied for the scene, every template's run and every texture run: a copy of a
    // canopy never stepped is the canopy its constructor builds, so every sample is what three separate
    // builds gave.
    explicit UmbrellaScene(const DropOnCanopyConfig& config) : UmbrellaScene(config, DropOnCanopy::fresh_canopy(config)) {}
    UmbrellaScene(const DropOnCanopyConfig& config, const Canopy& prototype)
        : drops(config, prototype),
          templates(record_impact_templates(config, prototype)),
          texture(calibrate_texture(config, templates, prototype)) {}
    DropOnCanopy drops;
    ImpactTemplateTable templates;
    TextureCalibration texture;
};

}  // namespace ameoto
