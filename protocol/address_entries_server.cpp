// SPDX-License-Identifier: GPL-3.0-or-later
// The server's rows of the OSC address table (address_entries.hpp): its state, notifications, peers,
// version, sync and quit, and where a sender's replies go (/reply/port); none of them changes the sound.
#include "protocol/address_entries.hpp"

#include <cstdint>

namespace ameoto::protocol::entries {

void add_server_entries(std::vector<AddressSpec>& t) {
    t.push_back({"/status", {}, "Ask for the server's state.", "/status.reply",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::status;
                     return std::nullopt;
                 }});
    t.push_back({"/notify",
                 {{"on", ArgumentKind::integer, "", 0.0, 1.0, false, "1: subscribe the sender, 0: unsubscribe it"}},
                 "Subscribe to (1) or leave (0) the server's notifications: /status.reply every second and /meter ten "
                 "times a second, sent to the address (or TCP connection) the /notify came from. At most 16 subscribers.",
                 "/done /notify (or /fail /notify when 16 already listen)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::notify;
                     r.notify_on = a.numbers[0] != 0.0;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/notify.reply i 1|0: whether the sender is subscribed"};
    t.push_back({"/nodes", {},
                 "Ask for the state of every node this one conducts (its peers, docs/nodes.md): this node first, then each peer.",
                 "/nodes.reply i nodes, then per node: s address (self for this one), i answering (1|0), f seconds since its last "
                 "answer (-1: never), f drops per second, f CPU average (%), i xruns, f rain rate (mm/h)",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::nodes;
                     return std::nullopt;
                 }});
    t.push_back({"/nodes/block", {},
                 "In a bundle: its timed commands go on the start of the audio block nearest the bundle's time (a conducting "
                 "node sends it with every bundle it times, on one of its block starts: nodes whose clocks differ by "
                 "microseconds then change at the same sample).",
                 "",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::on_block;
                     return std::nullopt;
                 }});
    t.push_back({"/version", {}, "Ask for the server's version.",
                 "/version.reply s program, s version, i protocol version, i UDP port, i TCP port (0: off)",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::version;
                     return std::nullopt;
                 }});
    t.push_back({"/sync",
                 {{"id", ArgumentKind::integer, "", -2147483648.0, 2147483647.0, false, "any integer, echoed back"}},
                 "Reply /synced id once everything sent before it is applied.",
                 "/synced",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::sync;
                     r.command.id = static_cast<std::int32_t>(a.numbers[0]);
                     return std::nullopt;
                 }});
    t.push_back({"/quit", {}, "Stop the server cleanly (the WAV is finalised).", "/done /quit",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::quit;
                     return std::nullopt;
                 }});
}

void add_reply_port_entry(std::vector<AddressSpec>& t) {
    // Appended (issue 7): Max's [udpsend] sends from a port it never listens on, so it cannot hear replies
    // sent back to the sender (scsynth's rule). As Ardour's OSC surface does ("reply manual port"), a
    // sender may name the port its replies go to; the address stays the sender's own.
    t.push_back({"/reply/port",
                 {{"port", ArgumentKind::integer, "", 0.0, 65535.0, false,
                   "UDP port on the sender's own IP address for every later reply to it; 0 = back to the port it sends from",
                   "7771"}},
                 "Send every later reply to this sender (/done, /fail, /synced, query replies, /status.reply, /notify's "
                 "/status.reply and /meter, /notice) to its IP address at PORT instead of the port it sends from. UDP only "
                 "(a TCP client's replies come back on its connection). At most 4096 senders redirected at once.",
                 "/done /reply/port (already sent to the new port); /fail /reply/port over TCP or when 4096 senders are redirected",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::reply_port;
                     r.reply_port = static_cast<int>(a.numbers[0]);
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/reply/port.reply i port: where this sender's replies go (0: the port it sends from)"};
}

}  // namespace ameoto::protocol::entries
