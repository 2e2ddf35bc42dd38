// SPDX-License-Identifier: GPL-3.0-or-later
// What a scene is allowed to be: surface kinds and their materials, names, the whole-scene check
// (validate_scene: the same limits as a file and OSC, scene_fields.hpp) and the rain's drop size
// distribution. Reading and writing scene files is scene_file.cpp; the built-in scenes builtin_scenes.cpp.
#include "engine/scene/scene_description.hpp"

#include <algorithm>
#include <set>
#include <utility>

#include "engine/scene/output_format.hpp"
#include "engine/scene/scene_fields.hpp"

namespace ameoto {

SceneFileError::SceneFileError(std::string file, int line, std::string field, const std::string& reason)
    : std::runtime_error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) +
                         (field.empty() ? std::string() : ": " + field) + ": " + reason),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)) {}

const char* surface_kind_name(SurfaceKind kind) {
    switch (kind) {
        case SurfaceKind::umbrella: return "umbrella";
        case SurfaceKind::water: return "water";
        case SurfaceKind::plate: return "plate";
        case SurfaceKind::ground: return "ground";
    }
    return "?";
}

std::optional<SurfaceKind> surface_kind(std::string_view name) {
    for (SurfaceKind k : {SurfaceKind::umbrella, SurfaceKind::water, SurfaceKind::plate, SurfaceKind::ground})
        if (name == surface_kind_name(k)) return k;
    return std::nullopt;
}

std::vector<std::string> surface_materials(SurfaceKind kind) {
    switch (kind) {
        case SurfaceKind::umbrella: return {"nylon", "vinyl", "pvc", "seed-nylon"};
        case SurfaceKind::water: return {"pond", "puddle"};
        case SurfaceKind::plate: return {"tin", "glass", "car-roof"};
        case SurfaceKind::ground: return {"leaves", "soil"};
    }
    return {};
}

bool is_scene_name(std::string_view name) {
    if (name.empty() || name.size() > 32) return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    });
}

std::string validate_scene(const SceneDescription& s) {
    using namespace scene_fields;
    if (s.version < 1 || s.version > scene_format_version)
        return "version " + std::to_string(s.version) + " is not 1 to " + std::to_string(scene_format_version);
    if (s.accuracy)
        if (const std::string why = validate_accuracy_budget(*s.accuracy); !why.empty()) return why;
    if (!is_scene_name(s.name)) return "scene name '" + s.name + "' is not 1-32 of A-Z a-z 0-9 - _";
    const RainDescription& r = s.rain;
    for (const std::string& why : {check_number("rain rate", r.rate_mm_per_h, rate_range, "mm/h"),
                                   check_number("wind", r.wind_m_per_s, wind_range, "m/s"),
                                   check_number("gust", r.gustiness, gust_range, ""),
                                   check_number("gamma mu", r.gamma_mu, mu_range, ""),
                                   check_number("gamma lambda", r.gamma_lambda_per_mm, lambda_range, "1/mm"),
                                   check_number("listener x", s.listener.x_m, position_range, "m"),
                                   check_number("listener y", s.listener.y_m, position_range, "m"),
                                   check_number("listener z", s.listener.z_m, position_range, "m"),
                                   check_number("lod budget", s.lod.budget_percent, budget_range, "%"),
                                   check_number("lod full", s.lod.max_full, full_range, "drops"),
                                   check_number("output gain", s.gain_db, gain_range, "dB")})
        if (!why.empty()) return why;
    if (!s.output_format.empty()) {
        std::string why;
        if (!parse_output_format(s.output_format, why)) return "output format " + why;
    }
    if (std::find(dsd_names().begin(), dsd_names().end(), r.dsd) == dsd_names().end())
        return "dsd '" + r.dsd + "' is not one of marshall-palmer, joss-drizzle, joss-thunderstorm, gamma";
    if (!std::isfinite(r.wind_direction_rad) || std::abs(r.wind_direction_rad) > 4.0 * constants::pi)
        return "wind direction " + number(r.wind_direction_rad / degrees) + " deg is outside -720..720";
    if (!std::isfinite(s.listener.facing_rad) || std::abs(s.listener.facing_rad) > 4.0 * constants::pi)
        return "listener facing " + number(s.listener.facing_rad / degrees) + " deg is outside -720..720";
    if (s.surfaces.size() > static_cast<std::size_t>(max_scene_surfaces))
        return "more than " + std::to_string(max_scene_surfaces) + " surfaces";
    std::set<std::string> names;
    int umbrellas = 0;
    for (const SurfaceDescription& f : s.surfaces) {
        const std::string which = "surface '" + f.name + "': ";
        if (!is_scene_name(f.name)) return "surface name '" + f.name + "' is not 1-32 of A-Z a-z 0-9 - _";
        if (!names.insert(f.name).second) return which + "a second surface of that name";
        const auto materials = surface_materials(f.kind);
        if (f.kind != SurfaceKind::umbrella && std::find(materials.begin(), materials.end(), f.material) == materials.end()) {
            std::string list;
            for (const auto& m : materials) list += (list.empty() ? "" : ", ") + m;
            return which + "material '" + f.material + "' is not one of " + list + " for a " + surface_kind_name(f.kind);
        }
        if (f.kind == SurfaceKind::umbrella && !is_scene_name(f.material))
            return which + "material '" + f.material + "' is not a material name";
        for (const std::string& why : {check_number("size x", f.size_x_m, size_range, "m"),
                                       check_number("size y", f.size_y_m, size_range, "m"),
                                       check_number("x", f.x_m, position_range, "m"),
                                       check_number("y", f.y_m, position_range, "m"),
                                       check_number("z", f.z_m, position_range, "m")})
            if (!why.empty()) return which + why;
        if (f.node < 1 || f.node > max_scene_nodes)
            return which + "node " + std::to_string(f.node) + " is outside 1.." + std::to_string(max_scene_nodes);
        if (f.kind == SurfaceKind::umbrella) {
            if (!in(panels_range, f.panels)) return which + "panels " + std::to_string(f.panels) + " is outside 3..16";
            if (f.size_x_m > 3.0) return which + "an umbrella's diameter " + number(f.size_x_m) + " m is outside 0.05..3";
            if (++umbrellas > 1) return which + "a scene has at most one umbrella";
        }
    }
    return "";
}

DropSizeDistribution drop_size_distribution_for(const RainDescription& rain) {
    if (rain.dsd == "joss-drizzle") return DropSizeDistribution::joss_drizzle();
    if (rain.dsd == "joss-thunderstorm") return DropSizeDistribution::joss_thunderstorm();
    if (rain.dsd == "gamma") {
        if (rain.gamma_lambda_per_mm > 0.0) return DropSizeDistribution::gamma(rain.gamma_mu, rain.gamma_lambda_per_mm);
        DropSizeDistribution d = DropSizeDistribution::gamma_zhang(4.1);
        d.lambda_exponent = -0.21;
        return d;
    }
    return DropSizeDistribution::marshall_palmer();
}

}  // namespace ameoto
