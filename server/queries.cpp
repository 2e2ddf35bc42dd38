// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/queries.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/method_choice.hpp"
#include "protocol/address_table.hpp"

namespace ameoto {
namespace {

double degrees(double radians) { return radians * (180.0 / 3.14159265358979323846); }   // replies use the units of the requests

// /accuracy with no arguments: the scene's budget (off 0 when none) and the method it chose
// (core/method_choice.hpp): measure, budget, method, sub-steps asked, modes kept (0: all), why.
std::vector<protocol::OscArgument> accuracy_reply(const SceneDescription& scene) {
    using protocol::OscArgument;
    const AccuracyBudget budget = scene.accuracy.value_or(AccuracyBudget{});
    const MethodSetting setting = scene.accuracy ? choose_method(budget).method.setting : MethodSetting{};
    const std::string why = scene.accuracy ? choose_method(budget).reason : "no budget: the default method";
    return {OscArgument::from_string(scene.accuracy ? accuracy_measure_name(budget.measure) : "off"),
            OscArgument::from_float(static_cast<float>(scene.accuracy ? budget.value : 0.0)),
            OscArgument::from_string(method_label(setting)), OscArgument::from_int(setting.sub_steps),
            OscArgument::from_int(setting.modes), OscArgument::from_string(why)};
}

}  // namespace

void Queries::answer(const Peer& to, const std::string& address, const std::string& name) {
    using protocol::OscArgument;
    auto f = [](double v) { return OscArgument::from_float(static_cast<float>(v)); };
    auto text = [](const std::string& v) { return OscArgument::from_string(v); };
    auto reply = [&](const std::string& reply_address, const std::vector<OscArgument>& args) { replies_.reply(to, reply_address, args); };
    const std::string reply_address = address + ".reply";
    const SceneDescription& scene = record_.scene();
    auto surface = std::find_if(scene.surfaces.begin(), scene.surfaces.end(), [&](const SurfaceDescription& x) { return x.name == name; });
    if (address == "/rain/rate") {
        reply(reply_address, {f(scene.rain.rate_mm_per_h)});
    } else if (address == "/rain/wind") {
        reply(reply_address, {f(scene.rain.wind_m_per_s), f(degrees(scene.rain.wind_direction_rad)), f(scene.rain.gustiness)});
    } else if (address == "/rain/dsd") {
        reply(reply_address, {text(scene.rain.dsd), f(scene.rain.gamma_mu), f(scene.rain.gamma_lambda_per_mm)});
    } else if (address == "/listener") {
        const ListenerDescription& l = scene.listener;
        reply(reply_address, {f(l.x_m), f(l.y_m), f(l.z_m), f(degrees(l.facing_rad))});
    } else if (address == "/listener/orientation") {
        const auto& o = record_.orientation();
        reply(reply_address, {f(degrees(o[0])), f(degrees(o[1])), f(degrees(o[2]))});
    } else if (address == "/gain") {
        reply(reply_address, {f(scene.gain_db)});
    } else if (address == "/loudness") {
        reply(reply_address, {text(level_.automatic ? "auto" : "physical"), f(level_.target_lufs),
                              f(std::isfinite(level_.measured_lufs) ? level_.measured_lufs : -200.0), f(level_.level_gain_db),
                              f(scene.gain_db), f(full_scale_spl_db(level_.full_scale_pa, level_.level_gain_db + scene.gain_db))});
    } else if (address == "/lod") {
        reply(reply_address, {f(scene.lod.budget_percent), OscArgument::from_int(scene.lod.max_full)});
    } else if (address == "/material/liquid") {
        const Liquid& l = record_.liquid();
        reply(reply_address, {text(l.name), f(l.density), f(l.surface_tension), f(l.viscosity)});
    } else if (address == "/material/surface") {
        if (surface == scene.surfaces.end() || surface->kind != SurfaceKind::umbrella) {
            reply("/fail", protocol::fail_arguments(address, "no surface named '" + name + "' with a membrane material "
                                                             "(/surface/set " + name + " tells any surface's material)"));
            return;
        }
        const MembraneMaterial& m = record_.material();
        reply(reply_address, {text(name), text(m.name), f(m.areal_density), f(m.tension), f(m.mass_damping), f(m.stiffness_damping)});
    } else if (address == "/surface/set") {
        if (surface == scene.surfaces.end()) {
            reply("/fail", protocol::fail_arguments(address, "no surface named '" + name + "'"));
            return;
        }
        const SurfaceDescription& x = *surface;
        reply(reply_address, {text(x.name), text(surface_kind_name(x.kind)), text(x.material), f(x.size_x_m), f(x.size_y_m), f(x.x_m),
                              f(x.y_m), f(x.z_m)});
    } else if (address == "/surfaces") {
        std::vector<OscArgument> names;
        for (const SurfaceDescription& x : scene.surfaces) names.push_back(text(x.name));
        reply(reply_address, names);
    } else if (address == "/scene" || address == "/scene/load") {
        reply(reply_address, {text(scene.name)});
    } else if (address == "/accuracy") {
        reply(reply_address, accuracy_reply(scene));
    } else if (address == "/canopy/air") {
        const auto umbrella = std::find_if(scene.surfaces.begin(), scene.surfaces.end(),
                                           [](const SurfaceDescription& x) { return x.kind == SurfaceKind::umbrella; });
        reply(reply_address, {OscArgument::from_int(umbrella != scene.surfaces.end() && umbrella->air ? 1 : 0)});
    } else if (address == "/canopy/impact") {
        const auto umbrella = std::find_if(scene.surfaces.begin(), scene.surfaces.end(),
                                           [](const SurfaceDescription& x) { return x.kind == SurfaceKind::umbrella; });
        reply(reply_address, {text(impact_model_name(umbrella != scene.surfaces.end() ? umbrella->impact : ImpactModel::wet))});
    } else if (address == "/reply/port") {
        reply(reply_address, {OscArgument::from_int(replies_.reply_port_of(to))});
    } else if (address == "/notify") {
        reply(reply_address, {OscArgument::from_int(subscriptions_.has(to) ? 1 : 0)});
    } else {
        // A settable address whose query the table announces but the daemon does not answer: a new
        // address needs its branch above, from the applied state (query_table_test lists them).
        reply("/fail", protocol::fail_arguments(address, "this server cannot answer the query of " + address + " yet"));
    }
}

void Queries::version(const Peer& to) {
    using protocol::OscArgument;
    replies_.reply(to, "/version.reply",
                   {OscArgument::from_string("ameotod"), OscArgument::from_string(AMEOTO_VERSION),
                    OscArgument::from_int(protocol::protocol_version), OscArgument::from_int(udp_port_), OscArgument::from_int(tcp_port_)});
}

}  // namespace ameoto
