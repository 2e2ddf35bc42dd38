// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A whole scene built off the audio thread for /scene/load: its umbrella (always built, so the renderer's
// /drop, templates and texture have a canopy; heard only when the scene has one) and its other surfaces,
// with the settings the scene file gives (rain rate, level of detail). The renderer takes the parts by
// pointer and hands the empty envelope back; the old parts ring out for 0.5 s and come back separately.
//
// Interface:
//   auto loaded = make_loaded_scene(renderer_config, scene_description);   // throws std::invalid_argument
//   Command c{.kind = CommandKind::load_scene, .object = loaded.release()};

#include <memory>

#include "engine/render/scene_surfaces.hpp"
#include "engine/render/umbrella_scene.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto {

struct LoadedScene {
    std::unique_ptr<UmbrellaScene> umbrella;
    std::unique_ptr<SceneSurfaces> surfaces;
    std::unique_ptr<RainSpawner> rain;   // the umbrella's, for the scene's drop size distribution
    bool has_umbrella = true;
    double rain_rate_mm_per_h = 2.0;
    double lod_budget = 0.4;
    int max_full = 4;
    double wind_m_per_s = 0.0, wind_direction_rad = 0.0, gustiness = 0.0;
    double level_gain_db = 0.0;   // the scene's level gain (chosen off the audio thread: level_choice.hpp)
    double gain_db = 0.0;         // the listening gain the scene asks for (its `output gain=`)
};

}  // namespace ameoto
