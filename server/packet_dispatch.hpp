// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What a packet becomes: decoded and validated (protocol/receive.hpp), then each message acted on in
// order, a bundle's messages all timed against one reading of the audio clock. A change to the sound
// goes to the audio thread through the command queue (answered /fail busy when it is full) and into
// the scene record; a scene, surface, material or liquid change goes to the scene manager; a query, a
// /notify, /reply/port, /version or /status is answered; a refusal is /fail address reason and changes
// nothing. Another server's replies arriving as requests are dropped unanswered.
//
// Interface:
//   PacketDispatch dispatch(bridge, scenes, record, replies, queries, subscriptions, status, traffic,
//                           [&] { loop.shutdown_soon(); }, peers);   // what /quit does after its /done
//   peers (--peers, peers.hpp): every accepted change to the sound is also sent to them, and applied here
//   at the same timetag (now + --peer-latency, or the bundle's own when later); their /status.reply
//   answers are taken; /nodes answers for the set. A message from a peer is never sent on (no loops).
//   dispatch.handle(bytes, size, peer);     // one UDP datagram or TCP packet
//   dispatch.closed(peer);                  // its TCP connection went: no one's subscriber any more
//   bool reply = is_reply_address("/done"); // the server's own reply addresses (never answered)
//
// Thread: the control thread only. The TCP endpoint posts its packets here (osc_intake.hpp).

#include <cstddef>
#include <functional>
#include <string>

#include "server/osc/peer.hpp"
#include "server/osc/traffic_counters.hpp"
#include "server/peers.hpp"
#include "server/queries.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/replies.hpp"
#include "server/scene_manager.hpp"
#include "server/scene_record.hpp"
#include "server/status.hpp"
#include "server/subscriptions.hpp"

namespace ameoto {

bool is_reply_address(const std::string& address);

class PacketDispatch {
public:
    PacketDispatch(AudioBridge& bridge, SceneManager& scenes, SceneRecord& record, Replies& replies, Queries& queries,
                   Subscriptions& subscriptions, StatusReport& status, TrafficCounters& traffic, std::function<void()> quit,
                   PeerSet& peers)
        : bridge_(bridge), scenes_(scenes), record_(record), replies_(replies), queries_(queries), subscriptions_(subscriptions),
          status_(status), traffic_(traffic), quit_(std::move(quit)), peers_(peers) {}
    void handle(const unsigned char* data, std::size_t size, const Peer& sender);
    void closed(const Peer& gone) { subscriptions_.forget(gone); }

private:
    void enqueue(Command c, const protocol::DecodedMessage& message, const AudioClock& clock, const Peer& sender, bool conduct,
                 bool on_block);

    AudioBridge& bridge_;
    SceneManager& scenes_;
    SceneRecord& record_;
    Replies& replies_;
    Queries& queries_;
    Subscriptions& subscriptions_;
    StatusReport& status_;
    TrafficCounters& traffic_;
    std::function<void()> quit_;
    PeerSet& peers_;
};

}  // namespace ameoto
