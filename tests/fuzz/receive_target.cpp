// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/fuzz/receive_target.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "engine/scene/scene_description.hpp"
#include "protocol/receive.hpp"

namespace {

using namespace ameoto;
using namespace ameoto::protocol;

[[noreturn]] void broken(const char* invariant, const std::string& detail) {
    std::fprintf(stderr, "fuzz invariant broken: %s: %s\n", invariant, detail.c_str());
    std::abort();
}

// What the daemon keeps between messages, as far as validation and saving depend on it.
struct ServerState {
    SceneDescription scene = *builtin_scene("umbrella");
    std::map<std::string, Liquid> liquids;
    std::map<std::string, MembraneMaterial> materials;
    ProtocolContext context;

    ServerState() {
        context.surfaces = {"umbrella"};
        // The default umbrella's canopy seen from above: a disc of radius 0.5 m (the daemon asks the
        // canopy's geometry; the exact shape does not matter to the receive path).
        context.on_surface = [](const std::string&, double x, double y) { return x * x + y * y <= 0.25; };
        context.custom_liquid = [this](const std::string& name) -> std::optional<Liquid> {
            auto it = liquids.find(name);
            return it == liquids.end() ? std::nullopt : std::optional<Liquid>(it->second);
        };
        context.custom_material = [this](const std::string& name) -> std::optional<MembraneMaterial> {
            auto it = materials.find(name);
            return it == materials.end() ? std::nullopt : std::optional<MembraneMaterial>(it->second);
        };
    }
};

void check_finite(const Command& c, const std::string& address) {
    for (double v : c.values)
        if (!std::isfinite(v)) broken("an accepted command carries finite values", address);
}

// A scene the server accepted must save and load back: /scene/save writes format_scene's text.
void check_saves_and_loads(const SceneDescription& scene, const std::string& address) {
    if (!validate_scene(scene).empty()) return;   // the daemon refuses it; nothing to save
    try {
        const SceneDescription back = parse_scene(format_scene(scene), "fuzz.scene");
        if (back.surfaces.size() != scene.surfaces.size()) broken("a saved scene loads back whole", address);
    } catch (const SceneFileError& e) {
        broken("a valid scene saves to a file that loads", address + ": " + e.what() + "\n" + format_scene(scene));
    }
}

// The scene changes Daemon::State::on_packet (scene_after) and edit_scene make for an accepted request.
void apply(ServerState& s, const DecodedMessage& m, const Request& r) {
    SceneDescription next = s.scene;
    switch (r.action) {
        case Action::enqueue: {
            check_finite(r.command, m.address);
            next = scene_after(s.scene, r.command);
            if (!validate_scene(next).empty()) return;   // the daemon refuses it
            break;
        }
        case Action::set_liquid:
            if (!r.liquid) broken("set_liquid carries a liquid", m.address);
            if (!find_liquid(r.liquid->name)) s.liquids[r.liquid->name] = *r.liquid;
            break;
        case Action::set_surface_material:
            if (!r.material) broken("set_surface_material carries a material", m.address);
            if (!membrane_material(r.material->name)) s.materials[r.material->name] = *r.material;
            for (SurfaceDescription& f : next.surfaces)
                if (f.kind == SurfaceKind::umbrella) f.material = r.material->name;
            break;
        case Action::load_scene:
        case Action::save_scene:
            if (!is_scene_name(r.scene_name)) broken("a scene name is a name, not a path", r.scene_name);
            break;
        case Action::edit_scene: {
            using Op = SceneEdit::Op;
            auto found = std::find_if(next.surfaces.begin(), next.surfaces.end(),
                                      [&](const SurfaceDescription& f) { return f.name == r.edit.surface.name; });
            if (r.edit.op == Op::dsd) {
                next.rain.dsd = r.edit.dsd;
                next.rain.gamma_mu = r.edit.mu;
                next.rain.gamma_lambda_per_mm = r.edit.lambda;
            } else if (r.edit.op == Op::surface_add && found == next.surfaces.end()) {
                next.surfaces.push_back(r.edit.surface);
            } else if (r.edit.op == Op::surface_set && found != next.surfaces.end() && found->kind != SurfaceKind::umbrella) {
                *found = r.edit.surface;
            } else if (r.edit.op == Op::surface_remove && found != next.surfaces.end()) {
                next.surfaces.erase(found);
            }
            // The daemon applies an edit only when the edited scene validates.
            if (!validate_scene(next).empty()) return;
            break;
        }
        case Action::status:
        case Action::query:
        case Action::notify:
        case Action::version:
        case Action::reply_port:
        case Action::set_loudness:
        case Action::nodes:
        case Action::on_block:
        case Action::quit: break;   // they change no scene
    }
    // A message the server accepted keeps a valid scene valid: otherwise /scene/save and every later
    // scene edit would be refused for a reason the client never caused.
    if (validate_scene(s.scene).empty() && !validate_scene(next).empty())
        broken("an accepted message keeps the scene valid", m.address + ": " + validate_scene(next));
    check_saves_and_loads(next, m.address);
    s.scene = next;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    ServerState state;
    const ReceivedPacket packet = receive_packet(data, size, state.context);
    if (packet.failed()) {
        if (!packet.messages.empty()) broken("a packet that fails is refused whole", packet.fail_reason);
        encode_message("/fail", fail_arguments(packet.fail_address, packet.fail_reason));   // the reply
        return 0;
    }
    for (const ReceivedMessage& m : packet.messages) {
        if (!m.validation.ok) {
            if (m.validation.reason.empty()) broken("a refusal gives a reason", m.message.address);
            encode_message("/fail", fail_arguments(m.message.address, m.validation.reason));
            continue;
        }
        if (!m.validation.reason.empty()) broken("an accepted message has no refusal", m.validation.reason);
        if (!find_address(m.message.address)) broken("only table addresses are accepted", m.message.address);
        apply(state, m.message, m.validation.request);
    }
    return 0;
}
