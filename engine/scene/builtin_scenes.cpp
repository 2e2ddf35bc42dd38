// SPDX-License-Identifier: GPL-3.0-or-later
// The built-in scenes (umbrella, pond, tin-roof, forest, street): what `ameoto render scene --scene NAME`,
// `ameotod --scene NAME` and /scene/load NAME find before the scene folder (scene_description.hpp).
#include "engine/scene/scene_description.hpp"

#include <utility>

namespace ameoto {

std::vector<std::string> builtin_scene_names() { return {"umbrella", "pond", "tin-roof", "forest", "street"}; }

std::optional<SceneDescription> builtin_scene(std::string_view name) {
    SceneDescription s;
    s.name = std::string(name);
    auto surface = [](std::string n, SurfaceKind k, std::string m, double sx, double sy, double x, double y, double z) {
        SurfaceDescription f;
        f.name = std::move(n);
        f.kind = k;
        f.material = std::move(m);
        f.size_x_m = sx;
        f.size_y_m = sy;
        f.x_m = x;
        f.y_m = y;
        f.z_m = z;
        return f;
    };
    // The listener stands at the origin, ears at 1.6 m; the umbrella is held over the head (its shaft
    // top 0.3 m above the ears, as the renderer's canopy listener).
    // The canopy in air (docs/canopy-air.md): the air's mass on the fabric and its unbaffled radiation.
    SurfaceDescription umbrella = surface("umbrella", SurfaceKind::umbrella, "nylon", 1.0, 1.0, 0.0, 0.0, 1.9);
    umbrella.air = true;
    if (name == "umbrella") {
        s.rain.rate_mm_per_h = 2.0;
        s.surfaces = {umbrella};
    } else if (name == "pond") {
        // Light rain by a pond: where the 13-25 kHz bubble peak of light rain is heard best.
        s.rain.rate_mm_per_h = 1.5;
        s.rain.dsd = "joss-drizzle";
        s.surfaces = {surface("pond", SurfaceKind::water, "pond", 4.0, 3.0, 3.0, 0.0, 0.0),
                      surface("bank", SurfaceKind::ground, "soil", 4.0, 2.0, 0.0, 0.0, 0.0)};
    } else if (name == "tin-roof") {
        // Inside a shed: the roof 1 m above the head, heavy rain.
        s.rain.rate_mm_per_h = 20.0;
        s.surfaces = {surface("roof-left", SurfaceKind::plate, "tin", 1.0, 0.6, 0.0, 0.4, 2.6),
                      surface("roof-right", SurfaceKind::plate, "tin", 1.0, 0.6, 0.0, -0.4, 2.6)};
    } else if (name == "forest") {
        s.rain.rate_mm_per_h = 8.0;
        s.rain.wind_m_per_s = 3.0;
        s.rain.gustiness = 0.3;
        // The patches a listener hears apart from the hiss: a few square metres each (the leaves of a
        // whole forest would be millions of drops per second, far beyond what single drops add).
        s.surfaces = {surface("leaves-near", SurfaceKind::ground, "leaves", 2.0, 2.0, 2.0, 1.0, 4.0),
                      surface("leaves-far", SurfaceKind::ground, "leaves", 3.0, 3.0, -6.0, -4.0, 6.0),
                      surface("floor", SurfaceKind::ground, "soil", 3.0, 3.0, 0.0, 0.0, 0.0),
                      surface("puddle", SurfaceKind::water, "puddle", 0.8, 0.6, 1.5, -1.0, 0.0)};
    } else if (name == "street") {
        s.rain.rate_mm_per_h = 10.0;
        s.rain.wind_m_per_s = 2.0;
        s.rain.gustiness = 0.2;
        s.surfaces = {umbrella,
                      surface("car", SurfaceKind::plate, "car-roof", 1.2, 1.0, 2.5, -1.5, 1.4),
                      surface("window", SurfaceKind::plate, "glass", 0.8, 0.6, -2.0, 2.0, 1.0),
                      surface("puddle", SurfaceKind::water, "puddle", 1.0, 0.8, 1.0, 1.0, 0.0)};
    } else {
        return std::nullopt;
    }
    return s;
}

}  // namespace ameoto
