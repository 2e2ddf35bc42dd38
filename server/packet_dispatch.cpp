// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/packet_dispatch.hpp"

#include <time.h>

#include <cmath>

#include "engine/models/ambisonics.hpp"
#include "protocol/receive.hpp"

namespace ameoto {
namespace {
double dispatch_wall_now() {
    timespec t{};
    clock_gettime(CLOCK_REALTIME, &t);
    return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
}
// The first start of one of this node's audio blocks at or after t (unix seconds). A time the conductor
// chooses is put there: each node turns a timetag into a sample by rounding (frame_at), and the nodes'
// clocks put a block's start a few microseconds apart (netjack2's slaves wake one after the other for
// the same master cycle); a time in the middle of a sample would round to different samples on two nodes
// as often as not, a block's start (a whole sample on every node) only when they are half a sample
// (10 us at 48 kHz) apart.
// A peer receives such a time with /nodes/block in its bundle and moves it to its own block start nearest
// it: the nodes' block starts for one cycle lie microseconds apart, far less than half a block, so every
// node lands on the same cycle's first sample (measured between two netjack2 slaves on one host: 9 us).
double on_block_grid(const AudioClock& clock, double t, int block, bool nearest) {
    if (!clock.valid || block <= 0) return t;
    const double start = static_cast<double>(clock.unix_ns) * 1e-9;
    const double in_blocks = (t - start) * clock.sample_rate / block;
    return start + (nearest ? std::round(in_blocks) : std::ceil(in_blocks)) * block / clock.sample_rate;
}
}  // namespace

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
    // Conducting: what this node accepts goes to its peers too, unless a peer sent it.
    const bool conduct = !peers_.empty() && !peers_.is_peer(sender);
    // /nodes/block anywhere in the packet: its timed commands go on this node's nearest block start.
    bool on_block = false;
    for (const auto& [message, v] : packet.messages) on_block = on_block || (v.ok && v.request.action == protocol::Action::on_block);
    for (const auto& [message, v] : packet.messages) {
        if (!v.ok) {
            if (message.address == "/status.reply" && peers_.answered(sender, message.args, record_, dispatch_wall_now())) continue;
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
            // A scene, material, liquid or loudness change rebuilds the scene off the audio thread (it cannot
            // land on a sample): it goes to the peers untimed, and each validates it again.
            case protocol::Action::set_liquid:
                scenes_.change_liquid(sender, message.address, *v.request.liquid);
                if (conduct) peers_.forward(message, std::nullopt);
                break;
            case protocol::Action::set_surface_material:
                scenes_.change_material(sender, message.address, *v.request.material);
                if (conduct) peers_.forward(message, std::nullopt);
                break;
            case protocol::Action::load_scene:
                scenes_.load(sender, message.address, v.request.scene_name);
                if (conduct) peers_.forward(message, std::nullopt);
                break;
            case protocol::Action::save_scene: scenes_.save(sender, message.address, v.request.scene_name); break;
            case protocol::Action::edit_scene:
                scenes_.edit(sender, message.address, v.request.edit);
                if (conduct) peers_.forward(message, std::nullopt);
                break;
            case protocol::Action::enqueue: enqueue(v.request.command, message, clock, sender, conduct, on_block); break;
            case protocol::Action::on_block: break;   // read before the loop
            case protocol::Action::nodes:
                replies_.reply(sender, "/nodes.reply", peers_.nodes_reply(status_.arguments(), dispatch_wall_now()));
                break;
            case protocol::Action::query: queries_.answer(sender, v.request.query_address, v.request.query_text); break;
            case protocol::Action::notify: subscriptions_.set(sender, v.request.notify_on); break;
            case protocol::Action::version: queries_.version(sender); break;
            case protocol::Action::reply_port: replies_.set_reply_port(sender, v.request.reply_port); break;
            case protocol::Action::set_loudness:
                scenes_.set_loudness(sender, message.address, v.request.loudness_lufs);
                if (conduct) peers_.forward(message, std::nullopt);
                break;
        }
    }
}

// A command for the audio thread: timed by its bundle's timetag, refused when it would leave a scene
// that cannot be saved and rebuilt (e.g. /listener must not carry the umbrella out of range); the
// record itself changes once the queue has taken it.
void PacketDispatch::enqueue(Command c, const protocol::DecodedMessage& message, const AudioClock& clock, const Peer& sender,
                             bool conduct, bool on_block) {
    if (protocol::changes_scene(c.kind)) {
        if (const std::string why = record_.refusal(c); !why.empty()) {
            replies_.reply(sender, "/fail", protocol::fail_arguments(message.address, why));
            return;
        }
    }
    c.reply_to = replies_.know(sender);
    // Conducting, every node applies it at one time: --peer-latency from now (the time a datagram takes
    // to reach the peers and be queued there), or the bundle's own time when that is later. /sync is
    // this node's own queue's question: not sent on, not delayed.
    // A time on a block start (chosen here, or asked for with /nodes/block) is sent on with /nodes/block.
    const bool forward = conduct && c.kind != CommandKind::sync;
    const bool asked_on_block = on_block;
    on_block = false;
    std::optional<double> at;
    if (message.bundled && !message.timetag.immediate()) at = message.timetag.to_unix_seconds();
    const double soonest = forward ? dispatch_wall_now() + peers_.latency_s() : 0.0;
    if (forward && (!at || *at < soonest)) {
        at = on_block_grid(clock, soonest, status_.block_size(), false);
        on_block = true;
    } else if (asked_on_block && at) {
        at = on_block_grid(clock, *at, status_.block_size(), true);
        on_block = true;
    }
    if (at) {
        c.timed = true;
        c.frame = frame_at(clock, *at);
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
    if (forward) peers_.forward(message, at, on_block);
    // What the queries answer: an untimed change from now on (the audio thread applies it at its next
    // block); a timed one once its frame has played.
    if (!protocol::changes_scene(c.kind)) return;   // rain, wind, listener, lod; not /drop, /sync
    if (!c.timed || c.frame <= bridge_.snapshot().frames) record_.apply(c);
    else record_.apply_at_frame(c);
}

}  // namespace ameoto
