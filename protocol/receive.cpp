// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/receive.hpp"

namespace ameoto::protocol {

std::string packet_address(const unsigned char* data, std::size_t size) {
    if (size >= 8 && std::string(reinterpret_cast<const char*>(data), 7) == "#bundle") return "#bundle";
    std::string address;
    for (std::size_t i = 0; i < size && i < 64 && data[i] != 0; ++i) address += static_cast<char>(data[i]);
    return address.empty() || address[0] != '/' ? std::string("") : address;
}

bool changes_scene(CommandKind kind) {
    return kind == CommandKind::rain_rate || kind == CommandKind::wind || kind == CommandKind::listener || kind == CommandKind::lod ||
           kind == CommandKind::gain || kind == CommandKind::orientation;
}

SceneDescription scene_after(SceneDescription scene, const Command& c) {
    if (c.kind == CommandKind::rain_rate) scene.rain.rate_mm_per_h = c.values[0];
    if (c.kind == CommandKind::wind) {
        scene.rain.wind_m_per_s = c.values[0];
        scene.rain.wind_direction_rad = c.values[1];
        scene.rain.gustiness = c.values[2];
    }
    if (c.kind == CommandKind::listener) {
        for (SurfaceDescription& f : scene.surfaces)
            if (f.kind == SurfaceKind::umbrella) {
                f.x_m += c.values[0] - scene.listener.x_m;
                f.y_m += c.values[1] - scene.listener.y_m;
                f.z_m += c.values[2] - scene.listener.z_m;
            }
        scene.listener = ListenerDescription{c.values[0], c.values[1], c.values[2], c.values[3]};
    }
    if (c.kind == CommandKind::gain) scene.gain_db = c.values[0];
    if (c.kind == CommandKind::lod) {
        scene.lod.budget_percent = 100.0 * c.values[0];
        scene.lod.max_full = static_cast<int>(c.values[1]);
    }
    return scene;
}

ReceivedPacket receive_packet(const void* data, std::size_t size, const ProtocolContext& context) {
    ReceivedPacket out;
    DecodedPacket packet = decode_packet(data, size);
    if (!packet.error.empty()) {
        out.fail_address = packet_address(static_cast<const unsigned char*>(data), size);
        out.fail_reason = std::move(packet.error);
        return out;
    }
    out.messages.reserve(packet.messages.size());
    for (auto& message : packet.messages) {
        Validation v = validate(message, context);
        out.messages.push_back({std::move(message), std::move(v)});
    }
    return out;
}

}  // namespace ameoto::protocol
