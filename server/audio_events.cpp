// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/audio_events.hpp"

#include "protocol/address_table.hpp"

namespace ameoto {

bool AudioEvents::handle() {
    RendererEvent e;
    bool freed_scene = false;
    while (bridge_.poll_event(e)) {
        const auto& to = replies_.peer(e.reply_to);
        if (e.kind == RendererEventKind::retired) {
            // Freed here, never on the audio thread, each as its type.
            if (e.object_type == RetiredObject::scene_surfaces) delete static_cast<SceneSurfaces*>(e.object);
            else if (e.object_type == RetiredObject::loaded_scene) delete static_cast<LoadedScene*>(e.object);
            else if (e.object_type == RetiredObject::rotation) {
                delete static_cast<AmbixRotation*>(e.object);   // 2 KiB: no need to return memory for it
                continue;
            } else delete static_cast<UmbrellaScene*>(e.object);
            freed_scene = true;
        } else if (e.kind == RendererEventKind::swapped) {
            const char* address = e.command == CommandKind::swap_surface  ? "/material/surface"
                                  : e.command == CommandKind::swap_liquid ? "/material/liquid"
                                                                          : "/lod";
            if (e.command == CommandKind::load_scene) {
                // /scene/load, /rain/dsd or a /surface/...: the address waiting for it, in order.
                replies_.reply(to, "/done", {protocol::OscArgument::from_string(scenes_.done_address(e.reply_to))});
            } else {
                replies_.reply(to, "/done", {protocol::OscArgument::from_string(address)});
            }
        } else if (e.kind == RendererEventKind::synced) {
            replies_.reply(to, "/synced", {protocol::OscArgument::from_int(e.id)});
        } else {
            const char* address = e.command == CommandKind::drop        ? "/drop"
                                  : e.command == CommandKind::rain_rate ? "/rain/rate"
                                  : e.command == CommandKind::lod       ? "/lod"
                                                                        : "/sync";
            ++traffic_.busy;
            replies_.reply(to, "/fail", protocol::fail_arguments(address, "busy: too many scheduled commands"));
        }
    }
    return freed_scene;
}

}  // namespace ameoto
