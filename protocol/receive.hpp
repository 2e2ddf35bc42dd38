// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One received datagram -> what the server must do about each message in it, without sockets or
// state: decode (osc_codec), then validate each message (address_table). The daemon acts on the
// result; the fuzzer (tests/fuzz/) and the table tests feed it bytes directly, so what they exercise
// is exactly the daemon's receive path.
//
// Interface:
//   ReceivedPacket p = receive_packet(bytes, size, context);
//   if (p.failed()) reply /fail p.fail_address p.fail_reason;        // the packet did not decode
//   for (const ReceivedMessage& m : p.messages)
//       m.validation.ok ? act on m.validation.request : reply /fail m.message.address m.validation.reason;
//
//   if (changes_scene(command.kind))                          // rain rate, wind, listener, lod:
//       next = scene_after(current, command);                 // what the command changes in the scene;
//       if (!validate_scene(next).empty()) reply /fail ...;   // refused when that is not valid
//
// A packet that does not decode is refused whole (nothing in it is acted on); within a bundle that
// decodes, each message is validated and refused on its own (as scsynth does).

#include <cstddef>
#include <string>
#include <vector>

#include "protocol/address_table.hpp"
#include "protocol/osc_codec.hpp"

namespace ameoto::protocol {

struct ReceivedMessage {
    DecodedMessage message;
    Validation validation;
};

struct ReceivedPacket {
    std::vector<ReceivedMessage> messages;   // empty when the packet failed
    std::string fail_address;                // the packet's own address when it starts like a message,
                                             // "#bundle" for a bundle, "" otherwise
    std::string fail_reason;                 // empty when the packet decoded
    bool failed() const { return !fail_reason.empty(); }
};

ReceivedPacket receive_packet(const void* data, std::size_t size, const ProtocolContext& context);

// The scene as an accepted command leaves it: rain rate, wind, listener (an umbrella is carried: it
// keeps its place over the listener's head) and level of detail; other commands change nothing. The
// daemon refuses the command when the result does not validate (a listener moved so far that the
// carried umbrella would leave the scene's range), so /scene/save always has a valid scene to write.
SceneDescription scene_after(SceneDescription scene, const Command& command);
bool changes_scene(CommandKind kind);   // rain_rate, wind, listener, lod, gain, orientation (the
                                        // head's: not in the scene, but kept with it for its query)

// The address a /fail for an undecodable packet names (at most 64 characters of it).
std::string packet_address(const unsigned char* data, std::size_t size);

}  // namespace ameoto::protocol
