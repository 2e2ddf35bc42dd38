// SPDX-License-Identifier: GPL-3.0-or-later
// The level rows of the OSC address table (address_entries.hpp): the level of detail (/lod), the
// listening gain (/gain) and --level auto's loudness target (/loudness).
#include "protocol/address_entries.hpp"

namespace ameoto::protocol::entries {

void add_level_entries(std::vector<AddressSpec>& t) {
    t.push_back({"/lod",
                 {{"budget", ArgumentKind::number, "%", 1.0, 95.0, false,
                   "share of the block period the engine aims to spend; beyond it, detail is shed"},
                  {"full", ArgumentKind::integer, "drops", 0.0, 64.0, false, "most lattice drops (full model) at once"}},
                 "Set the level-of-detail budget and the most full-model drops at once.",
                 "/done /lod (once in effect)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::lod;
                     r.command.values[0] = a.numbers[0] / 100.0;
                     r.command.values[1] = a.numbers[1];
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/lod.reply f budget (%), i full (drops)"};
    t.push_back({"/gain",
                 {{"gain", ArgumentKind::number, "dB", -80.0, 80.0, false,
                   "listening gain on top of the level (--level auto's or the physical one); ramps over 50 ms"}},
                 "Set the listening gain (docs/loudness.md). 0 dBFS is then 133.98 dB SPL less the level gain and this gain.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.command.kind = CommandKind::gain;
                     r.command.values[0] = a.numbers[0];
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/gain.reply f gain (dB): the listening gain last applied"};
    t.push_back({"/loudness",
                 {{"target", ArgumentKind::number, "LUFS", -60.0, -5.0, false,
                   "integrated loudness each scene's default rain is played at (--level auto only)"}},
                 "Set --level auto's target loudness: the scene playing moves to it at once (ramped over 50 ms), and "
                 "every scene loaded later is measured and set to it.",
                 "",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::set_loudness;
                     r.loudness_lufs = a.numbers[0];
                     return std::nullopt;
                 }});
    t.back().query = {true, {},
                      "/loudness.reply s level (auto|physical), f target (LUFS), f measured (LUFS: the scene's default rain "
                      "at the physical scale), f level gain (dB), f gain (dB), f full scale (dB SPL: what 0 dBFS is now)"};
}

}  // namespace ameoto::protocol::entries
