// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the renderer swaps as one piece when a material or liquid changes: the umbrella scene with its
// lattice drops (the full level of detail), the impact templates recorded from them (the template level
// of detail) and the texture grains' calibration from those (the texture level), all for the same
// material, liquid, geometry and sample rate.
//
// Interface (all off the audio thread):
//   UmbrellaScene scene(drop_on_canopy_config);   // builds one canopy (in air its modes, ~0.6 s) and the
//                                                 // scene on a copy, then records the templates from
//                                                 // copies (~0.5 s) and calibrates the texture (~0.2 s)
//   UmbrellaScene scene(config, prototype);       // the same from the caller's canopy, never stepped
//   UmbrellaParts parts(config);                  // the canopy, templates and texture alone, built once...
//   UmbrellaScene a(config, parts), b(other, parts);   // ...for any number of scenes: each copies them
//                                                 // (no build); throws std::invalid_argument unless
//                                                 // parts.fits(other)
//   scene.drops        // DropOnCanopy: canopy, drop pool, collider, far field
//   scene.templates    // ImpactTemplateTable (impact_templates.hpp)
//   scene.texture      // TextureCalibration (texture_grains.hpp)
//
// Why UmbrellaParts: --level auto renders a scene to measure it, then plays it (level_choice.hpp). The
// two differ only in the rain and, for an Ambisonic bus, in the listener the measurement hears, none of
// which the parts depend on: the templates are contact forces, and the texture is calibrated on its own
// mono listener. So one build serves both (docs/reliability.md, "Start-up cost": in air the build is
// about 0.7 s of CPU). A scene built from parts is the scene its own build gives, bit for bit (tested).

#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/impact_templates.hpp"
#include "engine/models/texture_grains.hpp"

namespace ameoto {

struct UmbrellaParts {
    explicit UmbrellaParts(const DropOnCanopyConfig& config);
    // Whether a scene of `other` may be built from these: its configuration is the one they were built
    // for, but for what they do not depend on (output, channels, listener style).
    bool fits(const DropOnCanopyConfig& other) const;

    DropOnCanopyConfig config;       // what they were built for
    Canopy canopy;                   // at rest, never stepped (copied into every scene)
    ImpactTemplateTable templates;   // recorded from copies of canopy
    TextureCalibration texture;      // calibrated from templates on copies of canopy
};

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
    UmbrellaScene(const DropOnCanopyConfig& config, const UmbrellaParts& parts);
    DropOnCanopy drops;
    ImpactTemplateTable templates;
    TextureCalibration texture;
};

}  // namespace ameoto
