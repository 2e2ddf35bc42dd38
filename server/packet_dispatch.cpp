// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/packet_dispatch.hpp"

#include "engine/models/ambisonics.hpp"
#include "protocol/receive.hpp"

namespace ameoto {

// The server's own replies (docs/PROTOCOL.md, "Replies"). One arriving as a request is another server's
// answer, or this server's own after a /reply/port aimed at a server's port: answering it with /fail
// would start an exchange that never ends, so it is dropped unanswered.
bool is_reply_address(const std::string& address) {
    return address == "/done" || address == "/fail" || address == "/synced" || address == "/notice" || address == "/meter" ||
           (address.size() > 6 && address.ends_with(".reply"));
}

void PacketDispatch::handle(const unsigned char* data, std::size_t size, const Peer& sender) {
    const protocol::ReceivedPacket packet = protocol::receive_packet(data, size, scenes_.context());
    if (packet.failed()) {
        replies_.reply(sender, "/fail", protocol::fail_arguments(packet.fail_address, packet.fail_reason));
        return;
    }
    // One clock reading for the whole packet: the messages of a bundle keep their distances to the sample.
    const AudioClock clock = bridge_.clock();
    for (const auto& [message, v] : packet.messages) {
        if (!v.ok) {
            if (!protocol::find_address(message.address) && is_reply_address(message.address)) continue;   // never answer a reply
            replies_.reply(sender, "/fail", protocol::fail_arguments(message.address, v.reason));
            continue;
        }
        switch (v.request.action) {
            case protocol::Action::status:
                replies_.know(sender);   // known from now on: it gets /notice (faults) like any client that sent a command
                replies_.reply(sender, "/status.reply", status_.arguments());
                break;
            case protocol::Action::quit:
                replies_.reply(sender, "/done", {protocol::OscArgument::from_string("/quit")});
                quit_();
                break;
            case protocol::Action::set_liquid: scenes_.change_liquid(sender, message.address, *v.request.liquid); break;
            case protocol::Action::set_surface_material: scenes_.change_material(sender, message.address, *v.request.material); break;
            case protocol::Action::load_scene: scenes_.load(sender, message.address, v.request.scene_name); break;
            case protocol::Action::save_scene: scenes_.save(sender, message.address, v.request.scene_name); break;
            case protocol::Action::edit_scene: scenes_.edit(sender, message.address, v.request.edit); break;
            case protocol::Action::enqueue: enqueue(v.request.command, message, clock, sender); break;
            case protocol::Action::query: queries_.answer(sender, v.request.query_address, v.request.query_text); break;
            case protocol::Action::notify: subscriptions_.set(sender, v.request.notify_on); break;
            case protocol::Action::version: queries_.version(sender); break;
            case protocol::Action::reply_port: replies_.set_reply_port(sender, v.request.reply_port); break;
            case protocol::Action::set_loudness: scenes_.set_loudness(sender, message.address, v.request.loudness_lufs); break;
        }
    }
}

// A command for the audio thread: timed by its bundle's timetag, refused when it would leave a scene
// that cannot be saved and rebuilt (e.g. /listener must not carry the umbrella out of range); the
// record itself changes once the queue has taken it.
void PacketDispatch::enqueue(Command c, const protocol::DecodedMessage& message, const AudioClock& clock, const Peer& sender) {
    if (protocol::changes_scene(c.kind)) {
        if (const std::string why = record_.refusal(c); !why.empty()) {
            replies_.reply(sender, "/fail", protocol::fail_arguments(message.address, why));
            return;
        }
    }
    c.reply_to = replies_.know(sender);
    if (message.bundled && !message.timetag.immediate()) {
        c.timed = true;
        c.frame = frame_at(clock, message.timetag.to_unix_seconds());
    }
    // The head's rotation matrix is built here, on the control thread, and travels with the command
    // (the audio thread copies it and hands it back in a `retired` event).
    if (c.kind == CommandKind::orientation)
        c.object = new AmbixRotation(AmbixRotation::from_orientation(c.values[0], c.values[1], c.values[2], scenes_.context().ambisonic_order));
    if (!bridge_.send(c)) {
        if (c.kind == CommandKind::orientation) delete static_cast<AmbixRotation*>(c.object);
        ++traffic_.busy;
        replies_.reply(sender, "/fail", protocol::fail_arguments(message.address, "busy: command queue full"));
        return;
    }
    // What the queries answer: an untimed change from now on (the audio thread applies it at its next
    // block); a timed one once its frame has played.
    if (!protocol::changes_scene(c.kind)) return;   // rain, wind, listener, lod; not /drop, /sync
    if (!c.timed || c.frame <= bridge_.snapshot().frames) record_.apply(c);
    else record_.apply_at_frame(c);
}

}  // namespace ameoto
