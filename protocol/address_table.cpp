// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/address_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/units.hpp"
#include "protocol/address_entries.hpp"

namespace ameoto::protocol {

std::string entries::format_number(double v) {
    // %.10g: enough digits that 500.0001 is not shown as 500 in "500.0001 is outside 0..500".
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", v);
    return text;
}

namespace {

using entries::format_number;

// The rows in the order of the listing (`ameoto send --help`, the fuzzer's corpus): each family's rows
// are in its file (address_entries.hpp); the listener's are here.
std::vector<AddressSpec> make_table() {
    std::vector<AddressSpec> t;
    entries::add_rain_and_drop_entries(t);
    entries::add_scene_entries(t);
    entries::add_wind_and_dsd_entries(t);
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
    entries::add_surface_entries(t);
    entries::add_level_entries(t);
    entries::add_material_entries(t);
    entries::add_server_entries(t);
    entries::add_accuracy_entry(t);
    entries::add_reply_port_entry(t);
    entries::add_canopy_air_entry(t);
    entries::add_canopy_impact_entry(t);
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
