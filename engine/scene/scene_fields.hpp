// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The scene fields' ranges and their text, shared by the checks (validate_scene: scene_description.cpp)
// and the file (parse_scene, format_scene: scene_file.cpp), so that a file, OSC and a saved scene accept
// the same values and write them so that they read back exactly. Internal to engine/scene: the interface
// is scene_description.hpp. Pure functions: any thread. Used through a using-directive inside function
// bodies only, so that no name leaks into the other sources of a unity build.

#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto::scene_fields {

inline constexpr double degrees = constants::pi / 180.0;

struct Range {
    double min, max;
};

// Ranges the file and OSC accept (the same limits as the OSC table's, protocol/address_entries_*.cpp,
// where they overlap).
inline constexpr Range rate_range{0.0, 500.0};          // mm/h
inline constexpr Range wind_range{0.0, 60.0};           // m/s: beyond a hurricane's 33 m/s
inline constexpr Range gust_range{0.0, 1.0};
inline constexpr Range mu_range{-2.0, 15.0};            // gamma shape: the observed range (Zhang et al. 2001)
inline constexpr Range lambda_range{0.0, 50.0};         // 1/mm (0: from the rate)
inline constexpr Range position_range{-1000.0, 1000.0}; // m
inline constexpr Range size_range{0.05, 100.0};         // m
inline constexpr Range budget_range{1.0, 95.0};         // % of the block period
inline constexpr Range full_range{0.0, 64.0};
inline constexpr Range panels_range{3.0, 16.0};
inline constexpr Range gain_range{-80.0, 80.0};         // dB: the listening gain (engine/render/output_stage.hpp)
inline constexpr Range node_range{1.0, static_cast<double>(max_scene_nodes)};

// The shortest text that reads back as the same double (so a saved scene reloads exactly).
inline std::string number(double v) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, v);
    return std::string(text, result.ptr);
}

inline bool in(Range r, double v) { return std::isfinite(v) && v >= r.min && v <= r.max; }

inline std::string range_text(Range r) { return number(r.min) + ".." + number(r.max); }

inline std::string check_number(const char* what, double v, Range r, const char* unit) {
    if (in(r, v)) return "";
    return std::string(what) + " " + number(v) + (unit[0] ? std::string(" ") + unit : "") + " is outside " + range_text(r);
}

inline const std::vector<std::string>& dsd_names() {
    static const std::vector<std::string> names{"marshall-palmer", "joss-drizzle", "joss-thunderstorm", "gamma"};
    return names;
}

// Angles are kept in radians and written in degrees: rounded to 1e-9 degree, so 30 degrees reads back
// as 30 (radians to degrees and back is not exact in binary).
inline std::string degrees_text(double rad) { return number(std::round(rad / degrees * 1e9) / 1e9); }

}  // namespace ameoto::scene_fields
