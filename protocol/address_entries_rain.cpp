// SPDX-License-Identifier: GPL-3.0-or-later
// The rain and its drops' rows of the OSC address table (address_entries.hpp): /rain/rate, /drop,
// /rain/wind, /rain/dsd.
#include "protocol/address_entries.hpp"

#include <algorithm>

#include "engine/core/units.hpp"

namespace ameoto::protocol::entries {

void add_rain_and_drop_entries(std::vector<AddressSpec>& t) {
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
}

void add_wind_and_dsd_entries(std::vector<AddressSpec>& t) {
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
}

}  // namespace ameoto::protocol::entries
