// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The renderer's setup parts, shared by the Renderer's constructor (renderer.cpp) and the scene building
// functions of renderer.hpp (configure_for_scene, apply_output_format, Renderer::make_scene,
// Renderer::make_loaded_scene: renderer_setup.cpp). Internal to engine/render: not an interface.
// Control thread only: they run before a Renderer exists or while one plays, off the audio thread.

#include "engine/render/renderer.hpp"

namespace ameoto::renderer_setup {

// config itself, or std::invalid_argument naming the first field out of its range.
const RendererConfig& checked(const RendererConfig& config);

// The output stage's share of config: channels, rate, gain and limiter.
OutputStageConfig output_config(const RendererConfig& config);

// The rain over this canopy (its area) with the scene's drop size distribution.
RainSpawner::Config rain_config_for(const Canopy& canopy, const RainDescription& rain);

}  // namespace ameoto::renderer_setup
