// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/subscriptions.hpp"

#include <algorithm>
#include <cmath>
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

// /meter f seconds (audio time at the window's end), i channels, then f peak and f RMS per channel, in dBFS,
// then f momentary and f short-term loudness (LUFS) and f true peak (dBTP).
// The newest window only: a subscriber wants the level now, and an offline render makes windows faster
// than anyone reads them.
void Subscriptions::send_meters() {
    MeterWindow newest, w;
    bool any = false;
    while (bridge_.take_meter(w)) {
        newest = w;
        any = true;
    }
    LoudnessTap& tap = bridge_.loudness_tap();
    tap.set_wanted(!subscribers_.empty());
    if (subscribers_.empty()) {
        loudness_.reset();
        return;
    }
    if (!loudness_)
        loudness_ = std::make_unique<LoudnessMeter>(bridge_.channels(), bridge_.sample_rate(), LoudnessMeter::short_term | LoudnessMeter::peaks);
    tap.drain(*loudness_);
    if (!any) return;
    std::vector<protocol::OscArgument> args{
        protocol::OscArgument::from_float(static_cast<float>(static_cast<double>(newest.frame) / backend_.sample_rate())),
        protocol::OscArgument::from_int(newest.channels)};
    for (int c = 0; c < newest.channels; ++c) {
        args.push_back(protocol::OscArgument::from_float(to_dbfs(newest.peak[c])));
        args.push_back(protocol::OscArgument::from_float(to_dbfs(newest.rms[c])));
    }
    // Loudness of the newest samples (EBU R 128: 400 ms momentary, 3 s short-term), and the true peak over
    // every channel since the previous /meter; below -120 (or silent) sent as -120.
    auto floor120 = [](double v) { return protocol::OscArgument::from_float(static_cast<float>(std::isfinite(v) ? std::max(v, -120.0) : -120.0)); };
    args.push_back(floor120(loudness_->momentary_lufs()));
    args.push_back(floor120(loudness_->short_term_lufs()));
    args.push_back(floor120(loudness_->true_peak_dbfs()));
    loudness_->reset_peaks();
    for (const Peer& p : subscribers_) replies_.reply(p, "/meter", args);
}

}  // namespace ameoto
