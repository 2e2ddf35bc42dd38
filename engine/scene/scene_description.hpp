// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What a rain scene is made of, as data: its surfaces, its rain, the listener and the level-of-detail
// budget; the built-in scenes; and the scene file format (text, versioned) that users write and that
// /scene/save writes.
//
// Interface:
//   SceneDescription s = builtin_scene("pond").value();     // umbrella (default), pond, tin-roof, forest, street
//   std::vector<std::string> names = builtin_scene_names();
//   SceneDescription s = parse_scene(text, "my.scene");      // throws SceneFileError (file, line, field, reason)
//   std::string text = format_scene(s);                      // parse_scene(format_scene(s)) == s
//   std::string why = validate_scene(s);                     // "" when valid (ranges, names, counts)
//
// Units: SI inside (m, m/s, rad); the file uses the units people write: rain in mm/h, wind direction
// and listener facing in degrees, sizes and positions in metres, the budget in % of the block period.
// Each key names its unit in docs/scenes.md.
//
// File format, version 1 (docs/scenes.md has the reference):
//   ameoto-scene 1                       first non-comment line: magic word and version
//   # comment                            blank lines and lines starting with # are ignored
//   name umbrella                        the scene's name
//   rain rate=2 dsd=marshall-palmer wind=0 direction=0 gust=0 [mu=2 lambda=3]
//   listener x=0 y=0 z=1.6 facing=0
//   lod budget=40 full=4
//   surface NAME kind=umbrella|water|plate|ground material=M size=X[xY] x= y= z= [panels=N]
// Version 2 adds one optional line (a version 1 file still loads; format_scene writes version 1 when
// the scene has no accuracy line, so older ameoto keep reading what needs nothing new):
//   accuracy cents=C | db=D              the accuracy budget (core/method_choice.hpp): the canopy runs the
//                                        cheapest measured method within C cents of frequency error or
//                                        D dB of log-spectral distance
// Version 3 adds one optional key on surface lines (what needs nothing new is still written as 1 or 2):
//   surface ... node=K                   the node (1..16) that renders this surface when the scene is
//                                        played by several ameotod (--node K); default 1. Every node
//                                        renders the same listener and rain (the same seed): the sum of
//                                        the nodes' outputs is the whole scene's (renderer.hpp)
// Version 4 adds one optional key on the output line:
//   output format=F                      the output format the scene asks for when a stream starts with it
//                                        and no --format is given (scene/output_format.hpp: stereo, ears,
//                                        ring:N, ambix:N, binaural); a running stream keeps its format
// Version 5 adds no key; it changes one default: an umbrella without an air key is in air (its canopy's
// air-loaded modes heard as dipoles, docs/canopy-air.md), where in versions 1-4 it is in vacuum, so a file
// written before keeps its sound. format_scene writes air=on whenever it is on, and so never needs 5:
//   surface NAME kind=umbrella ... [air=on|off] [impact=wet|seed]
// Keys after the first word are key=value pairs in any order; unknown keys, repeated keys, missing
// required keys and values out of range are errors naming the line and the key. A later version
// number is refused (the file needs a newer ameoto); lines are at most 1024 characters, files at most
// 64 KiB, surfaces at most 16.
//
// Coordinates: x forward, y left, z up (m), the ground at z = 0. A surface's (x, y, z) is its centre;
// an umbrella's is the top of its shaft, its size the canopy's plan diameter; a flat surface lies
// horizontal at height z.

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/method_choice.hpp"
#include "engine/models/wet_impact.hpp"
#include "engine/scene/drop_size_distribution.hpp"

namespace ameoto {

enum class SurfaceKind { umbrella, water, plate, ground };

struct SurfaceDescription {
    std::string name;                    // 1-32 of A-Z a-z 0-9 - _
    SurfaceKind kind = SurfaceKind::umbrella;
    std::string material;                // umbrella: nylon, vinyl, ...; water: pond, puddle; plate: tin,
                                         // glass, car-roof; ground: leaves, soil
    double size_x_m = 1.0, size_y_m = 1.0;   // umbrella: diameter (size_y = size_x); others: extent
    double x_m = 0.0, y_m = 0.0, z_m = 0.0;  // centre (umbrella: top of the shaft)
    int panels = 8;                      // umbrella only
    int node = 1;                        // the node that renders it, 1..max_scene_nodes (version 3)
    bool air = false;                    // umbrella only: air=on|off, the canopy in air (its air-loaded
                                         // modes heard as dipoles) or in vacuum, baffled (the seed's).
                                         // The built-in scenes, version-5 files and `render drop` put
                                         // it in air; a description built in code says so itself
    ImpactModel impact = ImpactModel::wet;   // umbrella only: impact=wet|seed, how a drop meets the canopy:
                                         // as a liquid (impulse m V, spreading; docs/impacts.md) or the
                                         // seed's elastic exchange (twice that impulse)
    bool operator==(const SurfaceDescription&) const = default;
};

struct RainDescription {
    double rate_mm_per_h = 2.0;          // mm/h (the published fits are written in it)
    std::string dsd = "marshall-palmer"; // marshall-palmer, joss-drizzle, joss-thunderstorm, gamma
    double gamma_mu = 2.0;               // gamma only: shape mu
    double gamma_lambda_per_mm = 0.0;    // gamma only: Lambda, 1/mm; 0 = from the rate (Zhang et al. 2001)
    double wind_m_per_s = 0.0;
    double wind_direction_rad = 0.0;     // where the wind blows towards, counter-clockwise from +x
    double gustiness = 0.0;              // 0..1: turbulence intensity of the gusts
    bool operator==(const RainDescription&) const = default;
};

struct ListenerDescription {
    double x_m = 0.0, y_m = 0.0, z_m = 1.6;   // the ears (standing height by default)
    double facing_rad = 0.0;                   // 0 = +x
    bool operator==(const ListenerDescription&) const = default;
};

struct LodDescription {
    double budget_percent = 40.0;        // of the block period the engine may spend (the governor's aim)
    int max_full = 4;                    // lattice drops at once (each awake costs about 2 us a sample)
    bool operator==(const LodDescription&) const = default;
};

struct SceneDescription {
    int version = 1;
    std::string name = "untitled";
    RainDescription rain;
    ListenerDescription listener;
    LodDescription lod;
    std::vector<SurfaceDescription> surfaces;
    std::optional<AccuracyBudget> accuracy;   // none: the engine's default method (explicit, as stable needs)
    double gain_db = 0.0;                // the listening gain (`output gain=DB`, /gain): dB on top of the level
    std::string output_format;           // `output format=F` (version 4): the text, checked by
                                         // parse_output_format; empty: not given
    bool operator==(const SceneDescription&) const = default;
};

inline constexpr int scene_format_version = 5;   // the newest this ameoto reads (and writes when needed)
// From version 5 on an umbrella is in air unless its line says air=off; in versions 1-4 it is in vacuum
// unless it says air=on (a file written before air was the default keeps the sound it was made with).
inline constexpr int scene_air_default_version = 5;
inline constexpr int max_scene_surfaces = 16;
inline constexpr int max_scene_nodes = 16;
inline constexpr std::size_t max_scene_line = 1024;
inline constexpr std::size_t max_scene_file_bytes = 64 * 1024;

class SceneFileError : public std::runtime_error {
public:
    SceneFileError(std::string file, int line, std::string field, const std::string& reason);
    const std::string& file() const { return file_; }
    int line() const { return line_; }            // 1-based; 0: the file as a whole
    const std::string& field() const { return field_; }

private:
    std::string file_;
    int line_;
    std::string field_;
};

std::optional<SceneDescription> builtin_scene(std::string_view name);
std::vector<std::string> builtin_scene_names();
SceneDescription parse_scene(std::string_view text, const std::string& file_name);
std::string format_scene(const SceneDescription& scene);
std::string validate_scene(const SceneDescription& scene);

const char* surface_kind_name(SurfaceKind kind);
std::optional<SurfaceKind> surface_kind(std::string_view name);
// The materials a surface kind accepts (an umbrella also accepts custom membrane materials by name
// once defined over OSC; the file names presets only).
std::vector<std::string> surface_materials(SurfaceKind kind);
bool is_scene_name(std::string_view name);   // 1-32 of A-Z a-z 0-9 - _ (never a path)

// The drop size distribution a scene's rain names (drop_size_distribution.hpp). gamma with lambda 0:
// the slope follows the rate as Marshall-Palmer's (4.1 R^-0.21 per mm) with mu from it (Zhang et al.
// 2001); otherwise the given mu and Lambda. Gamma distributions deliver exactly R of water.
DropSizeDistribution drop_size_distribution_for(const RainDescription& rain);

}  // namespace ameoto
