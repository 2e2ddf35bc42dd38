// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/subscriptions.hpp"

#include <algorithm>
#include <string>

#include "protocol/address_table.hpp"

namespace ameoto {

// /notify 1|0: subscribing twice is one subscription; leaving when not subscribed is not an error (both
// answer /done, so a patch can send either at any time).
void Subscriptions::set(const Peer& to, bool on) {
    const auto found = std::find(subscribers_.begin(), subscribers_.end(), to);
    if (on && found == subscribers_.end()) {
        if (subscribers_.size() >= max_subscribers) {
            replies_.reply(to, "/fail", protocol::fail_arguments("/notify", "too many subscribers: at most " + std::to_string(max_subscribers)));
            return;
        }
        subscribers_.push_back(to);
    }
    if (!on && found != subscribers_.end()) subscribers_.erase(found);
    replies_.reply(to, "/done", {protocol::OscArgument::from_string("/notify")});
}

bool Subscriptions::has(const Peer& peer) const {
    return std::find(subscribers_.begin(), subscribers_.end(), peer) != subscribers_.end();
}

// Each subscriber's reply is its own status (each takes the CPU peak since the one before).
void Subscriptions::send_status() {
    for (const Peer& p : std::vector<Peer>(subscribers_)) replies_.reply(p, "/status.reply", status_.arguments());
}

// /meter f seconds (audio time at the window's end), i channels, then f peak and f RMS per channel, in dBFS.
// The newest window only: a subscriber wants the level now, and an offline render makes windows faster
// than anyone reads them.
void Subscriptions::send_meters() {
    MeterWindow newest, w;
    bool any = false;
    while (bridge_.take_meter(w)) {
        newest = w;
        any = true;
    }
    if (!any || subscribers_.empty()) return;
    std::vector<protocol::OscArgument> args{
        protocol::OscArgument::from_float(static_cast<float>(static_cast<double>(newest.frame) / backend_.sample_rate())),
        protocol::OscArgument::from_int(newest.channels)};
    for (int c = 0; c < newest.channels; ++c) {
        args.push_back(protocol::OscArgument::from_float(to_dbfs(newest.peak[c])));
        args.push_back(protocol::OscArgument::from_float(to_dbfs(newest.rms[c])));
    }
    for (const Peer& p : subscribers_) replies_.reply(p, "/meter", args);
}

}  // namespace ameoto
