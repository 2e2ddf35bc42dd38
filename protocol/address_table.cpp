// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/address_table.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "engine/core/units.hpp"

namespace ameoto::protocol {
namespace {

std::string format_number(double v) {
    // %.10g: enough digits that 500.0001 is not shown as 500 in "500.0001 is outside 0..500".
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", v);
    return text;
}

// Names of custom liquids and materials: short, printable, no path characters (they may name files later).
std::optional<std::string> check_name(const std::string& name) {
    if (name.empty() || name.size() > 64) return "a name has 1 to 64 characters";
    for (const char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'))
            return "a name uses letters, digits, '-' and '_' only, not '" + std::string(1, c) + "'";
    return std::nullopt;
}

std::vector<AddressSpec> make_table() {
    std::vector<AddressSpec> t;
    t.push_back({"/rain/rate",
                 {{"rate", ArgumentKind::number, "mm/h", 0.0, 500.0, false, "rain rate; changes ramp over 1 s"}},
                 "Set the rain rate of the scene.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::rain_rate;
                     r.command.values[0] = a.numbers[0];
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/rain/rate.reply f rate (mm/h): the rate last applied (the sound ramps to it over 1 s)"};
    t.push_back({"/drop",
                 {{"diameter", ArgumentKind::number, "mm", 0.1, 8.0, false, "drop diameter"},
                  {"speed", ArgumentKind::number, "m/s", 0.0, 20.0, false, "impact speed; 0 = terminal speed (Gunn-Kinzer)"},
                  {"x", ArgumentKind::number, "m", -100.0, 100.0, false, "surface coordinate"},
                  {"y", ArgumentKind::number, "m", -100.0, 100.0, false, "surface coordinate"},
                  {"surface", ArgumentKind::text, "", 0, 0, true, "surface name; default umbrella", "umbrella"}},
                 "One drop now (or at the bundle's time) on a surface, at surface coordinates.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext& ctx, Request& r) -> std::optional<std::string> {
                     const std::string surface = a.texts.empty() ? std::string("umbrella") : a.texts[0];
                     if (std::find(ctx.surfaces.begin(), ctx.surfaces.end(), surface) == ctx.surfaces.end())
                         return "no surface named '" + surface + "'";
                     if (ctx.on_surface && !ctx.on_surface(surface, a.numbers[2], a.numbers[3]))
                         return "point (" + format_number(a.numbers[2]) + ", " + format_number(a.numbers[3]) +
                                ") m is not on surface '" + surface + "'";
                     r.command.kind = CommandKind::drop;
                     r.command.values[0] = units::mm_to_m(a.numbers[0]);
                     r.command.values[1] = a.numbers[1];
                     r.command.values[2] = a.numbers[2];
                     r.command.values[3] = a.numbers[3];
                     return std::nullopt;
                 }});
    auto scene_load = [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
        if (!is_scene_name(a.texts[0]))
            return "scene name '" + a.texts[0] + "' is not 1-32 of A-Z a-z 0-9 - _ (a name, not a path)";
        r.action = Action::load_scene;
        r.scene_name = a.texts[0];
        return std::nullopt;
    };
    t.push_back({"/scene",
                 {{"name", ArgumentKind::text, "", 0, 0, false,
                   "a built-in scene (umbrella, pond, tin-roof, forest, street) or one saved in the scene folder", "pond"}},
                 "Load a scene (the same as /scene/load, under the short name of the core contract).",
                 "/done /scene (once it plays)",
                 scene_load});
    t.back().query = {true, {}, "/scene.reply s name: the scene playing (its name as loaded or saved)"};
    t.push_back({"/scene/load",
                 {{"name", ArgumentKind::text, "", 0, 0, false,
                   "a built-in scene (umbrella, pond, tin-roof, forest, street) or one saved in the scene folder", "pond"}},
                 "Load a scene: its surfaces, rain, listener and level of detail; the old scene rings out.",
                 "/done /scene/load (once it plays)",
                 scene_load});
    t.back().query = {true, {}, "/scene/load.reply s name: the scene playing"};
    t.push_back({"/scene/save",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "the name to save the current scene under", "my-rain"}},
                 "Save the current scene (as it plays now) into the scene folder as NAME.scene, atomically.",
                 "/done /scene/save (once written)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     if (!is_scene_name(a.texts[0]))
                         return "scene name '" + a.texts[0] + "' is not 1-32 of A-Z a-z 0-9 - _ (a name, not a path)";
                     if (builtin_scene(a.texts[0]))
                         return "'" + a.texts[0] + "' is a built-in scene; save under another name";
                     r.action = Action::save_scene;
                     r.scene_name = a.texts[0];
                     return std::nullopt;
                 }});
    t.push_back({"/rain/wind",
                 {{"speed", ArgumentKind::number, "m/s", 0.0, 60.0, false, "mean wind speed; changes ramp over 1 s"},
                  {"direction", ArgumentKind::number, "deg", -720.0, 720.0, false,
                   "where the wind blows towards, counter-clockwise from x (forward)"},
                  {"gust", ArgumentKind::number, "", 0.0, 1.0, true, "gustiness: turbulence intensity (default 0, steady)"}},
                 "Set the wind: it tilts the rain, adds speed to the impacts, and gusts vary it.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::wind;
                     r.command.values[0] = a.numbers[0];
                     r.command.values[1] = units::deg_to_rad(a.numbers[1]);
                     r.command.values[2] = a.numbers.size() > 2 ? a.numbers[2] : 0.0;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/rain/wind.reply f speed (m/s), f direction (deg), f gust (0..1)"};
    t.push_back({"/rain/dsd",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "marshall-palmer, joss-drizzle, joss-thunderstorm or gamma",
                   "joss-drizzle"},
                  {"mu", ArgumentKind::number, "", -2.0, 15.0, true, "gamma: shape mu"},
                  {"lambda", ArgumentKind::number, "1/mm", 0.0, 50.0, true, "gamma: slope; 0 = from the rate (Zhang et al. 2001)"}},
                 "Set the drop size distribution of the rain.",
                 "/done /rain/dsd (once the new rain falls)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     const std::string& name = a.texts[0];
                     if (name != "marshall-palmer" && name != "joss-drizzle" && name != "joss-thunderstorm" && name != "gamma")
                         return "no drop size distribution named '" + name +
                                "' (marshall-palmer, joss-drizzle, joss-thunderstorm, gamma)";
                     if (name != "gamma" && !a.numbers.empty()) return "mu and lambda are for gamma only";
                     if (a.numbers.size() == 1) return "gamma takes mu and lambda together";
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::dsd;
                     r.edit.dsd = name;
                     if (a.numbers.size() == 2) {
                         r.edit.mu = a.numbers[0];
                         r.edit.lambda = a.numbers[1];
                     }
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/rain/dsd.reply s name, f mu, f lambda (1/mm; 0 = from the rate): mu and lambda matter for gamma only"};
    t.push_back({"/listener",
                 {{"x", ArgumentKind::number, "m", -1000.0, 1000.0, false, "ears, forward"},
                  {"y", ArgumentKind::number, "m", -1000.0, 1000.0, false, "ears, left"},
                  {"z", ArgumentKind::number, "m", -1000.0, 1000.0, false, "ears, up (the ground is 0)"},
                  {"facing", ArgumentKind::number, "deg", -720.0, 720.0, true, "facing, counter-clockwise from x (default 0)"}},
                 "Move the listener; the sound of every surface glides there (an umbrella is carried along).",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::listener;
                     for (int k = 0; k < 3; ++k) r.command.values[k] = a.numbers[static_cast<std::size_t>(k)];
                     r.command.values[3] = a.numbers.size() > 3 ? units::deg_to_rad(a.numbers[3]) : 0.0;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/listener.reply f x, f y, f z (m), f facing (deg)"};
    t.push_back({"/listener/orientation",
                 {{"yaw", ArgumentKind::number, "deg", -720.0, 720.0, false, "the head turned left (counter-clockwise from above)"},
                  {"pitch", ArgumentKind::number, "deg", -90.0, 90.0, false, "the nose raised"},
                  {"roll", ArgumentKind::number, "deg", -180.0, 180.0, false, "the right ear lowered"}},
                 "Turn the listener's head within the body (a head tracker): Ambisonics rotates the bus, stereo and "
                 "ring:N re-pan every sound by its turned direction; the scene is not rebuilt; the turn glides over 256 "
                 "samples. Refused on ears (docs/output-formats.md).",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext& context, Request& r) -> std::optional<std::string> {
                     if (context.ears)
                         return "the ears format hears the umbrella at two ear points fixed under it, so a head cannot turn "
                                "between them; use stereo, ring:N, ambix:N or binaural to track a head (/listener's facing "
                                "turns the listener in any format)";
                     r.command.kind = CommandKind::orientation;
                     for (int k = 0; k < 3; ++k) r.command.values[k] = units::deg_to_rad(a.numbers[static_cast<std::size_t>(k)]);
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/listener/orientation.reply f yaw, f pitch, f roll (deg): the head's orientation last applied"};
    auto surface_arguments = std::vector<ArgumentSpec>{
        {"name", ArgumentKind::text, "", 0, 0, false, "the surface's name (1-32 of A-Z a-z 0-9 - _)", "roof"},
        {"kind", ArgumentKind::text, "", 0, 0, false, "water, plate or ground (the umbrella comes with scenes)", "plate"},
        {"material", ArgumentKind::text, "", 0, 0, false, "water: pond, puddle; plate: tin, glass, car-roof; ground: leaves, soil",
         "tin"},
        {"size_x", ArgumentKind::number, "m", 0.05, 100.0, false, "extent along x"},
        {"size_y", ArgumentKind::number, "m", 0.05, 100.0, false, "extent along y"},
        {"x", ArgumentKind::number, "m", -1000.0, 1000.0, false, "centre"},
        {"y", ArgumentKind::number, "m", -1000.0, 1000.0, false, "centre"},
        {"z", ArgumentKind::number, "m", -1000.0, 1000.0, false, "height (the ground is 0)"}};
    auto surface_build = [](SceneEdit::Op op) {
        return [op](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
            SurfaceDescription f;
            f.name = a.texts[0];
            if (!is_scene_name(f.name)) return "surface name '" + f.name + "' is not 1-32 of A-Z a-z 0-9 - _";
            const auto kind = surface_kind(a.texts[1]);
            if (!kind || *kind == SurfaceKind::umbrella) return "kind '" + a.texts[1] + "' is not water, plate or ground";
            f.kind = *kind;
            f.material = a.texts[2];
            f.size_x_m = a.numbers[0];
            f.size_y_m = a.numbers[1];
            f.x_m = a.numbers[2];
            f.y_m = a.numbers[3];
            f.z_m = a.numbers[4];
            r.action = Action::edit_scene;
            r.edit.op = op;
            r.edit.surface = f;
            return std::nullopt;
        };
    };
    t.push_back({"/surface/add", surface_arguments, "Add a surface to the scene (rebuilt off the audio thread).",
                 "/done /surface/add (once it sounds)", surface_build(SceneEdit::Op::surface_add)});
    t.push_back({"/surface/set", surface_arguments, "Change a surface of the scene: kind, material, size, position.",
                 "/done /surface/set (once it sounds)", surface_build(SceneEdit::Op::surface_set)});
    t.back().query = {true,
                      {{"name", ArgumentKind::text, "", 0, 0, false, "a surface of the scene", "umbrella"}},
                      "/surface/set.reply s name, s kind, s material, f size_x, f size_y, f x, f y, f z (m)"};
    t.push_back({"/surfaces", {}, "List the surfaces of the scene playing.",
                 "/surfaces.reply s name ... (one string per surface, in the scene's order; none for an empty scene)",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::query;
                     r.query_address = "/surfaces";
                     return std::nullopt;
                 }});
    t.push_back({"/surface/remove",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "the surface's name", "roof"}},
                 "Remove a surface from the scene.",
                 "/done /surface/remove",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     if (!is_scene_name(a.texts[0])) return "surface name '" + a.texts[0] + "' is not 1-32 of A-Z a-z 0-9 - _";
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::surface_remove;
                     r.edit.surface.name = a.texts[0];
                     return std::nullopt;
                 }});
    t.push_back({"/lod",
                 {{"budget", ArgumentKind::number, "%", 1.0, 95.0, false,
                   "share of the block period the engine aims to spend; beyond it, detail is shed"},
                  {"full", ArgumentKind::integer, "drops", 0.0, 64.0, false, "most lattice drops (full model) at once"}},
                 "Set the level-of-detail budget and the most full-model drops at once.",
                 "/done /lod (once in effect)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::lod;
                     r.command.values[0] = a.numbers[0] / 100.0;
                     r.command.values[1] = a.numbers[1];
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/lod.reply f budget (%), i full (drops)"};
    t.push_back({"/gain",
                 {{"gain", ArgumentKind::number, "dB", -80.0, 80.0, false,
                   "listening gain on top of the level (--level auto's or the physical one); ramps over 50 ms"}},
                 "Set the listening gain (docs/loudness.md). 0 dBFS is then 133.98 dB SPL less the level gain and this gain.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::gain;
                     r.command.values[0] = a.numbers[0];
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/gain.reply f gain (dB): the listening gain last applied"};
    t.push_back({"/loudness",
                 {{"target", ArgumentKind::number, "LUFS", -60.0, -5.0, false,
                   "integrated loudness each scene's default rain is played at (--level auto only)"}},
                 "Set --level auto's target loudness: the scene playing moves to it at once (ramped over 50 ms), and "
                 "every scene loaded later is measured and set to it.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::set_loudness;
                     r.loudness_lufs = a.numbers[0];
                     return std::nullopt;
                 }});
    t.back().query = {true, {},
                      "/loudness.reply s level (auto|physical), f target (LUFS), f measured (LUFS: the scene's default rain "
                      "at the physical scale), f level gain (dB), f gain (dB), f full scale (dB SPL: what 0 dBFS is now)"};
    t.push_back({"/material/liquid",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "water, milk, heavy_oil, or a custom liquid's name", "water"},
                  {"density", ArgumentKind::number, "kg/m^3", LiquidLimits::density_min, LiquidLimits::density_max, true,
                   "custom liquid: density"},
                  {"surface_tension", ArgumentKind::number, "N/m", LiquidLimits::surface_tension_min,
                   LiquidLimits::surface_tension_max, true, "custom liquid: surface tension"},
                  {"viscosity", ArgumentKind::number, "Pa s", LiquidLimits::viscosity_min, LiquidLimits::viscosity_max, true,
                   "custom liquid: dynamic viscosity"}},
                 "Make drops of a preset liquid, or define a custom one (stored under its name) and use it.",
                 "/done /material/liquid (once the drops use it)",
                 [](const ValidatedArguments& a, const ProtocolContext& ctx, Request& r) -> std::optional<std::string> {
                     const std::string& name = a.texts[0];
                     if (auto refusal = check_name(name)) return refusal;
                     if (a.numbers.empty()) {
                         std::optional<Liquid> liquid = find_liquid(name);
                         if (!liquid && ctx.custom_liquid) liquid = ctx.custom_liquid(name);
                         if (!liquid) return "no liquid named '" + name + "' (presets: water, milk, heavy_oil)";
                         r.liquid = *liquid;
                     } else if (a.numbers.size() != 3) {
                         return "a custom liquid needs all three of density (kg/m^3), surface tension (N/m) and viscosity (Pa s)";
                     } else {
                         if (find_liquid(name)) return "'" + name + "' is a preset; give the custom liquid another name";
                         Liquid liquid{name, a.numbers[0], a.numbers[1], a.numbers[2]};
                         if (const std::string why = validate(liquid); !why.empty()) return why;
                         r.liquid = liquid;
                     }
                     r.action = Action::set_liquid;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/material/liquid.reply s name, f density (kg/m^3), f surface_tension (N/m), f viscosity (Pa s)"};
    t.push_back({"/material/surface",
                 {{"surface", ArgumentKind::text, "", 0, 0, false, "a surface of the scene (umbrella)", "umbrella"},
                  {"material", ArgumentKind::text, "", 0, 0, false, "nylon, seed-nylon, vinyl, or a custom material's name", "nylon"},
                  {"areal_density", ArgumentKind::number, "kg/m^2", 1e-3, 100.0, true, "custom material: mass per area"},
                  {"tension", ArgumentKind::number, "N/m", 0.1, 1e10, true, "custom material: membrane tension"},
                  {"mass_damping", ArgumentKind::number, "1/s", 0.0, 1e4, true, "custom material: Rayleigh alpha"},
                  {"stiffness_damping", ArgumentKind::number, "s", 0.0, 1e-3, true, "custom material: Rayleigh beta"}},
                 "Make a surface of a preset material, or define a custom one (stored under its name) and use it. "
                 "A material the surface's integrator cannot run stably is refused with the bound.",
                 "/done /material/surface (once the surface rings in it)",
                 [](const ValidatedArguments& a, const ProtocolContext& ctx, Request& r) -> std::optional<std::string> {
                     const std::string& surface = a.texts[0];
                     const std::string& name = a.texts[1];
                     if (std::find(ctx.surfaces.begin(), ctx.surfaces.end(), surface) == ctx.surfaces.end())
                         return "no surface named '" + surface + "'";
                     if (auto refusal = check_name(name)) return refusal;
                     // The umbrella's material is written into saved scenes, whose names are 1-32 characters.
                     if (!is_scene_name(name)) return "a material name has 1 to 32 characters";
                     if (a.numbers.empty()) {
                         std::optional<MembraneMaterial> material = membrane_material(name);
                         if (!material && ctx.custom_material) material = ctx.custom_material(name);
                         if (!material) return "no material named '" + name + "' (presets: nylon, seed-nylon, vinyl)";
                         r.material = *material;
                     } else if (a.numbers.size() != 4) {
                         return "a custom material needs all four of areal density (kg/m^2), tension (N/m), mass damping (1/s) "
                                "and stiffness damping (s)";
                     } else {
                         if (membrane_material(name)) return "'" + name + "' is a preset; give the custom material another name";
                         MembraneMaterial m = MembraneMaterial::custom(name, a.numbers[0], a.numbers[1], a.numbers[2], a.numbers[3]);
                         if (const MaterialCheck check = validate_membrane_material(m); !check.ok) return check.reason;
                         r.material = m;
                     }
                     r.surface = surface;
                     r.action = Action::set_surface_material;
                     return std::nullopt;
                 }});
    t.back().query = {true,
                      {{"surface", ArgumentKind::text, "", 0, 0, false, "a surface of the scene", "umbrella"}},
                      "/material/surface.reply s surface, s material, f areal_density (kg/m^2), f tension (N/m), f mass_damping (1/s), "
                      "f stiffness_damping (s)"};
    t.push_back({"/status", {}, "Ask for the server's state.", "/status.reply",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::status;
                     return std::nullopt;
                 }});
    t.push_back({"/notify",
                 {{"on", ArgumentKind::integer, "", 0.0, 1.0, false, "1: subscribe the sender, 0: unsubscribe it"}},
                 "Subscribe to (1) or leave (0) the server's notifications: /status.reply every second and /meter ten "
                 "times a second, sent to the address (or TCP connection) the /notify came from. At most 16 subscribers.",
                 "/done /notify (or /fail /notify when 16 already listen)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::notify;
                     r.notify_on = a.numbers[0] != 0.0;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/notify.reply i 1|0: whether the sender is subscribed"};
    t.push_back({"/nodes", {},
                 "Ask for the state of every node this one conducts (its peers, docs/nodes.md): this node first, then each peer.",
                 "/nodes.reply i nodes, then per node: s address (self for this one), i answering (1|0), f seconds since its last "
                 "answer (-1: never), f drops per second, f CPU average (%), i xruns, f rain rate (mm/h)",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::nodes;
                     return std::nullopt;
                 }});
    t.push_back({"/nodes/block", {},
                 "In a bundle: its timed commands go on the start of the audio block nearest the bundle's time (a conducting "
                 "node sends it with every bundle it times, on one of its block starts: nodes whose clocks differ by "
                 "microseconds then change at the same sample).",
                 "",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::on_block;
                     return std::nullopt;
                 }});
    t.push_back({"/version", {}, "Ask for the server's version.",
                 "/version.reply s program, s version, i protocol version, i UDP port, i TCP port (0: off)",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::version;
                     return std::nullopt;
                 }});
    t.push_back({"/sync",
                 {{"id", ArgumentKind::integer, "", -2147483648.0, 2147483647.0, false, "any integer, echoed back"}},
                 "Reply /synced id once everything sent before it is applied.",
                 "/synced",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::sync;
                     r.command.id = static_cast<std::int32_t>(a.numbers[0]);
                     return std::nullopt;
                 }});
    t.push_back({"/quit", {}, "Stop the server cleanly (the WAV is finalised).", "/done /quit",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::quit;
                     return std::nullopt;
                 }});
    // Appended (issue 6): the accuracy knob (engine/core/method_choice.hpp, docs/accuracy.md).
    t.push_back({"/accuracy",
                 {{"measure", ArgumentKind::text, "", 0, 0, false,
                   "cents (frequency error), db (log-spectral distance) or off (the default method)",
                   "off"},
                  {"budget", ArgumentKind::number, "cents or dB", AccuracyLimits::cents_min, AccuracyLimits::cents_max, true,
                   "the largest error allowed: cents 0.001..1200, db 0.001..60", "5"}},
                 "Set the scene's accuracy budget: the canopy runs the cheapest measured method within it (the scene is "
                 "rebuilt off the audio thread). With no arguments, ask for the budget and the method chosen.",
                 "/done /accuracy (once the rebuilt scene plays); with no arguments: /accuracy.reply",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     // Nothing is written into the request until the whole message is accepted.
                     std::optional<AccuracyBudget> accuracy;
                     if (a.texts[0] == "off") {
                         if (!a.numbers.empty()) return "'off' takes no budget";
                     } else {
                         AccuracyMeasure measure{};
                         if (!parse_accuracy_measure(a.texts[0], measure))
                             return "measure '" + a.texts[0].substr(0, 64) + "' is not one of cents, db, off";
                         if (a.numbers.empty()) return "give the budget: /accuracy " + a.texts[0] + " VALUE";
                         const AccuracyBudget budget{measure, a.numbers[0]};
                         if (std::string why = validate_accuracy_budget(budget); !why.empty()) return why;
                         accuracy = budget;
                     }
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::accuracy;
                     r.edit.accuracy = accuracy;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/accuracy.reply s measure, f budget, s method, i sub_steps, i modes, s why"};
    // Appended (issue 7): Max's [udpsend] sends from a port it never listens on, so it cannot hear replies
    // sent back to the sender (scsynth's rule). As Ardour's OSC surface does ("reply manual port"), a
    // sender may name the port its replies go to; the address stays the sender's own.
    t.push_back({"/reply/port",
                 {{"port", ArgumentKind::integer, "", 0.0, 65535.0, false,
                   "UDP port on the sender's own IP address for every later reply to it; 0 = back to the port it sends from",
                   "7771"}},
                 "Send every later reply to this sender (/done, /fail, /synced, query replies, /status.reply, /notify's "
                 "/status.reply and /meter, /notice) to its IP address at PORT instead of the port it sends from. UDP only "
                 "(a TCP client's replies come back on its connection). At most 4096 senders redirected at once.",
                 "/done /reply/port (already sent to the new port); /fail /reply/port over TCP or when 4096 senders are redirected",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::reply_port;
                     r.reply_port = static_cast<int>(a.numbers[0]);
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/reply/port.reply i port: where this sender's replies go (0: the port it sends from)"};
    // Appended (issue 19): the canopy in air or in vacuum (engine/models/air_canopy.hpp, docs/canopy.md).
    t.push_back({"/canopy/air",
                 {{"on", ArgumentKind::integer, "", 0.0, 1.0, false,
                   "1: the umbrella's canopy in air (its air-loaded modes heard as dipoles); 0: in vacuum, baffled (the seed's)",
                   "1"}},
                 "Put the scene's umbrella canopy in air (1) or in vacuum (0). The scene is rebuilt off the audio thread "
                 "and swapped in, as /material/surface does; saved scenes keep it (the umbrella's air= key). With no "
                 "arguments, ask which.",
                 "/done /canopy/air (once the rebuilt scene plays); /fail /canopy/air when the scene has no umbrella",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::air;
                     r.edit.air = a.numbers[0] != 0.0;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/canopy/air.reply i 1|0: whether the umbrella's canopy is in air (0 with no umbrella)"};
    return t;
}

const std::vector<AddressSpec>& table() {
    static const std::vector<AddressSpec> t = make_table();
    return t;
}

std::string describe(const ArgumentSpec& spec) {
    std::string s = spec.name;
    if (*spec.unit) s += std::string(" (") + spec.unit + ")";
    return s;
}

}  // namespace

std::span<const AddressSpec> address_table() { return table(); }

const AddressSpec* find_address(const std::string& address) {
    for (const auto& spec : table())
        if (address == spec.address) return &spec;
    return nullptr;
}

Validation validate(const DecodedMessage& message, const ProtocolContext& context) {
    Validation v;
    const AddressSpec* spec = find_address(message.address);
    if (!spec) {
        v.reason = "unknown address";
        return v;
    }
    if (spec->query.available && message.args.size() == spec->query.arguments.size() &&
        message.args.size() < spec->arguments.size()) {
        // The query form: no value, only what names the thing asked about (text, checked like a name).
        for (std::size_t i = 0; i < message.args.size(); ++i) {
            const OscArgument& arg = message.args[i];
            if (arg.type != 's' && arg.type != 'S') {
                v.reason = "argument " + std::to_string(i + 1) + " " + describe(spec->query.arguments[i]) +
                           ": expected a string, got type '" + std::string(1, arg.type) + "'";
                return v;
            }
            if (!is_scene_name(arg.text)) {
                v.reason = "'" + arg.text.substr(0, 64) + "' is not a surface name (1-32 of A-Z a-z 0-9 - _)";
                return v;
            }
            v.request.query_text = arg.text;
        }
        v.request.action = Action::query;
        v.request.query_address = spec->address;
        v.ok = true;
        return v;
    }
    const auto& specs = spec->arguments;
    const std::size_t required = static_cast<std::size_t>(
        std::count_if(specs.begin(), specs.end(), [](const ArgumentSpec& a) { return !a.optional; }));
    if (message.args.size() < required) {
        v.reason = "expected " + std::to_string(required) + (required == specs.size() ? "" : " to " + std::to_string(specs.size())) +
                   " arguments, got " + std::to_string(message.args.size());
        return v;
    }
    if (message.args.size() > specs.size()) {
        v.reason = "too many arguments: expected at most " + std::to_string(specs.size()) + ", got " +
                   std::to_string(message.args.size());
        return v;
    }
    ValidatedArguments values;
    for (std::size_t i = 0; i < message.args.size(); ++i) {
        const OscArgument& arg = message.args[i];
        const ArgumentSpec& as = specs[i];
        const std::string where = "argument " + std::to_string(i + 1) + " " + describe(as);
        if (as.kind == ArgumentKind::text) {
            if (arg.type != 's' && arg.type != 'S') {
                v.reason = where + ": expected a string, got type '" + std::string(1, arg.type) + "'";
                return v;
            }
            if (arg.text.size() > 255) {
                v.reason = where + ": longer than 255 characters";
                return v;
            }
            values.texts.push_back(arg.text);
            continue;
        }
        if (!arg.is_number()) {
            v.reason = where + ": expected a number, got type '" + std::string(1, arg.type) + "'";
            return v;
        }
        if (!std::isfinite(arg.number)) {
            v.reason = where + ": not a finite number";
            return v;
        }
        if (as.kind == ArgumentKind::integer && arg.number != std::floor(arg.number)) {
            v.reason = where + ": expected an integer, got " + format_number(arg.number);
            return v;
        }
        if (arg.number < as.min || arg.number > as.max) {
            v.reason = where + ": " + format_number(arg.number) + " is outside " + format_number(as.min) + ".." +
                       format_number(as.max);
            return v;
        }
        values.numbers.push_back(arg.number);
    }
    if (auto refusal = spec->build(values, context, v.request)) {
        v.reason = *refusal;
        return v;
    }
    v.ok = true;
    return v;
}

std::vector<OscArgument> fail_arguments(const std::string& address, const std::string& reason) {
    return {OscArgument::from_string(address), OscArgument::from_string(reason)};
}

}  // namespace ameoto::protocol
