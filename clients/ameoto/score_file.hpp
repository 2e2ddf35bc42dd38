// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A score file -> its timed OSC messages, for `ameoto render score`. Two formats, told apart by their
// first bytes:
//   - scsynth's binary score (what SuperCollider's Score.write writes, what scsynth -N reads): OSC
//     bundles one after the other, each preceded by its size in bytes as a big-endian int32; a bundle's
//     timetag is the time from the start of the render in seconds as OSC's 64-bit fixed point
//     (32 bits of whole seconds, 32 of fraction: no 1900 epoch), nested bundles as over UDP;
//   - a text score: one message a line, `TIME /address arg ...`; TIME in seconds from the start (a
//     number >= 0); arguments are read as `ameoto send` reads its words (integers -> i, numbers with
//     '.' or an exponent -> f, true/false -> T/F, anything else -> s), and "a quoted word" is always a
//     string (\" and \\ inside it); `#` starts a comment outside quotes; blank lines are skipped.
// Messages come out in time order (stable: equal times keep the file's order, as scsynth plays them).
//
// Interface (any thread; pure but for reading the file):
//   ScoreFile s = read_score_file(path);          // s.error: "FILE: ..." / "FILE:LINE: ..." when unreadable
//   ScoreFile s = parse_score(bytes, "name");     // the same from memory (tests)
//   for (const ScoreMessage& m : s.messages) ... m.seconds, m.message (address, args), m.where

#include <string>
#include <string_view>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::client {

struct ScoreMessage {
    double seconds = 0.0;              // from the start of the render
    protocol::DecodedMessage message;
    std::string where;                 // "FILE:LINE" (text) or "FILE: bundle N, message M" (binary), from 1
};

struct ScoreFile {
    bool binary = false;
    std::vector<ScoreMessage> messages;   // sorted by time, stable
    std::string error;                    // empty when the whole file was read
    // A recorded take (its first message /take/start: protocol/take_messages.hpp) cut short by a crash
    // mid-write: the bytes of the last, incomplete bundle, left out; every whole bundle before it is read.
    std::size_t cut_bytes = 0;
};

ScoreFile parse_score(std::string_view bytes, const std::string& name);
ScoreFile read_score_file(const std::string& path);

// Seconds as OSC's fixed point, and back (score timetags: seconds from the start, not since 1900).
protocol::Timetag score_timetag(double seconds);
double score_seconds(protocol::Timetag timetag);

}  // namespace ameoto::client
