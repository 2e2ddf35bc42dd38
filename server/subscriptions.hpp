// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// /notify subscribers (scsynth's convention): who they are, and what they get without asking, a
// /status.reply each second and the newest /meter window (peak and RMS per channel, then the loudness:
// momentary and short-term LUFS and true peak, measured here from the samples the audio thread hands over).
//
// Interface:
//   Subscriptions subs(replies, status, bridge, backend);
//   subs.set(peer, true);        // /notify 1|0: /done, or /fail when 16 already listen
//   subs.forget(peer);           // a TCP connection that closed
//   subs.has(peer)               // for the /notify query
//   subs.send_status();          // each second: /status.reply to each subscriber
//   subs.send_meters();          // each poll: the meter windows the audio thread finished, the newest sent
//
// Thread: the control thread only. Bounded: at most max_subscribers, so no number of clients can
// make the server send without end.

#include <cstddef>
#include <memory>
#include <vector>

#include "server/backends/backend.hpp"
#include "server/osc/peer.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/replies.hpp"
#include "server/status.hpp"

namespace ameoto {

class Subscriptions {
public:
    static constexpr std::size_t max_subscribers = 16;

    Subscriptions(Replies& replies, StatusReport& status, AudioBridge& bridge, const Backend& backend)
        : replies_(replies), status_(status), bridge_(bridge), backend_(backend) {}
    void set(const Peer& to, bool on);
    void forget(const Peer& gone) { std::erase(subscribers_, gone); }
    bool has(const Peer& peer) const;
    void send_status();
    void send_meters();

private:
    Replies& replies_;
    StatusReport& status_;
    AudioBridge& bridge_;
    const Backend& backend_;
    std::vector<Peer> subscribers_;
    std::unique_ptr<LoudnessMeter> loudness_;   // while anyone listens: momentary, short-term, true peak
};

}  // namespace ameoto
