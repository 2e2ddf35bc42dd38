// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// OSC packets <-> messages. liblo decodes and encodes each message (so its checks of type tags,
// padding and sizes apply); bundles are walked here so that every message keeps its bundle's
// timetag and the nesting depth is bounded.
//
// Interface:
//   DecodedPacket p = decode_packet(bytes, size);   // p.error empty on success
//   for (auto& m : p.messages) ... m.address, m.types, m.args, m.timetag (immediate unless bundled)
//   std::vector<unsigned char> bytes = encode_message(address, args);   // for replies
//
// Numbers arrive as whatever type the client chose (i, h, f, d); they are kept with their type tag
// and their value as double (and int64 for integers) so validation can coerce as scsynth does.

#include <cstdint>
#include <string>
#include <vector>

namespace ameoto::protocol {

// NTP timetag (seconds since 1900 and 2^-32 fractions). {0, 1} means "immediately" (OSC 1.0).
struct Timetag {
    std::uint32_t seconds = 0;
    std::uint32_t fraction = 1;
    bool immediate() const { return seconds == 0 && fraction <= 1; }
    double to_unix_seconds() const;   // seconds since 1970
    static Timetag from_unix_seconds(double unix_seconds);
};

struct OscArgument {
    char type = 'N';           // OSC type tag: i h f d s S T F N I c m b t
    double number = 0.0;       // numeric types, T/F as 1/0
    std::int64_t integer = 0;  // i and h exactly
    std::string text;          // s and S
    bool is_number() const { return type == 'i' || type == 'h' || type == 'f' || type == 'd'; }
    static OscArgument from_float(float v);
    static OscArgument from_int(std::int32_t v);
    static OscArgument from_int64(std::int64_t v);
    static OscArgument from_string(std::string v);
};

struct DecodedMessage {
    std::string address;
    std::string types;               // without the leading comma
    std::vector<OscArgument> args;
    Timetag timetag;                 // of the innermost enclosing bundle; immediate otherwise
    bool bundled = false;
};

struct DecodedPacket {
    std::vector<DecodedMessage> messages;
    std::string error;               // empty when the whole packet decoded
};

constexpr int max_bundle_depth = 8;

DecodedPacket decode_packet(const void* data, std::size_t size);
// Supports i h f d s S c T F N I; throws std::invalid_argument for any other type.
std::vector<unsigned char> encode_message(const std::string& address, const std::vector<OscArgument>& args);
std::vector<unsigned char> encode_bundle(Timetag timetag, const std::vector<std::vector<unsigned char>>& elements);

}  // namespace ameoto::protocol
