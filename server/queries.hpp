// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The answers to queries: ADDRESS with no value -> ADDRESS.reply with what is in effect (docs/PROTOCOL.md,
// "Queries"), from the scene record (what the engine has applied, not what was last asked for), and
// /version.
//
// Interface:
//   Queries queries(record, replies, subscriptions, scenes.level(), udp_port, tcp_port);
//   queries.answer(peer, "/rain/rate", "");          // /rain/rate.reply f, or /fail with the reason
//   queries.answer(peer, "/surface/set", "roof");    // a named surface's settings
//   queries.version(peer);                           // /version.reply ameotod VERSION protocol udp tcp
//
// Thread: the control thread only.

#include <string>

#include "server/level_state.hpp"
#include "server/osc/peer.hpp"
#include "server/replies.hpp"
#include "server/scene_record.hpp"
#include "server/subscriptions.hpp"

namespace ameoto {

class Queries {
public:
    Queries(const SceneRecord& record, Replies& replies, const Subscriptions& subscriptions, const LevelState& level, int udp_port,
            int tcp_port)
        : record_(record), replies_(replies), subscriptions_(subscriptions), level_(level), udp_port_(udp_port), tcp_port_(tcp_port) {}
    void answer(const Peer& to, const std::string& address, const std::string& name);
    void version(const Peer& to);

private:
    const SceneRecord& record_;
    Replies& replies_;
    const Subscriptions& subscriptions_;
    const LevelState& level_;   // the scene manager's
    int udp_port_;
    int tcp_port_;   // 0 without --tcp-port
};

}  // namespace ameoto
