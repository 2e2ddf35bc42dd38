// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/osc_codec.hpp"

#include <lo/lo.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace ameoto::protocol {

namespace {
// An OSC float (32 bits) as the decimal its sender most likely typed: the shortest text that reads back
// as the same float, read as a double. 1.6f is 1.60000002384...; the server works with 1.6, so a
// value saved back to a scene file reads as it was written. Exact for any float: distinct floats keep
// distinct shortest texts.
double float_as_typed(float f) {
    if (!std::isfinite(f)) return static_cast<double>(f);
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, f);
    double d = 0.0;
    std::from_chars(text, r.ptr, d);
    return d;
}
}  // namespace
namespace {

constexpr double ntp_unix_offset = 2208988800.0;   // seconds from 1900 to 1970

std::uint32_t read_be32(const unsigned char* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
void write_be32(std::vector<unsigned char>& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(v >> shift));
}

struct MessageDeleter {
    void operator()(lo_message m) const { lo_message_free(m); }
};
using MessagePtr = std::unique_ptr<std::remove_pointer_t<lo_message>, MessageDeleter>;

bool decode_message(const unsigned char* data, std::size_t size, Timetag tt, bool bundled, DecodedPacket& out) {
    int result = 0;
    MessagePtr msg(lo_message_deserialise(const_cast<unsigned char*>(data), size, &result));
    if (!msg) {
        out.error = "malformed OSC message (liblo error " + std::to_string(result) + ")";
        return false;
    }
    DecodedMessage m;
    m.address = reinterpret_cast<const char*>(data);   // deserialise checked it is terminated
    m.timetag = tt;
    m.bundled = bundled;
    const char* types = lo_message_get_types(msg.get());
    m.types = types ? types : "";
    lo_arg** argv = lo_message_get_argv(msg.get());
    for (std::size_t i = 0; i < m.types.size(); ++i) {
        OscArgument a;
        a.type = m.types[i];
        // liblo's argument pointers are only 4-byte aligned (OSC pads to 4), while lo_arg holds 8-byte
        // members: read each value by copying its bytes, never through lo_arg (a misaligned access,
        // undefined behaviour; found by the fuzzer under UBSan, tests/fuzz/crashes/crash-685b886e...).
        const auto* raw = reinterpret_cast<const unsigned char*>(argv[i]);
        switch (a.type) {
            case 'i': {
                std::int32_t v;
                std::memcpy(&v, raw, sizeof v);
                a.integer = v;
                a.number = v;
                break;
            }
            case 'h': {
                std::int64_t v;
                std::memcpy(&v, raw, sizeof v);
                a.integer = v;
                a.number = static_cast<double>(v);
                break;
            }
            case 'f': {
                float v;
                std::memcpy(&v, raw, sizeof v);
                a.number = float_as_typed(v);
                break;
            }
            case 'd': std::memcpy(&a.number, raw, sizeof a.number); break;
            case 's': case 'S': a.text = reinterpret_cast<const char*>(raw); break;
            case 'T': a.number = 1; break;
            case 'F': a.number = 0; break;
            case 'c': a.integer = raw[0]; a.number = raw[0]; break;   // lo_arg's c: the first byte
            default: break;   // N, I, m, b, t: kept by type only
        }
        m.args.push_back(std::move(a));
    }
    out.messages.push_back(std::move(m));
    return true;
}

bool decode_element(const unsigned char* data, std::size_t size, Timetag tt, bool bundled, int depth, DecodedPacket& out) {
    if (size >= 8 && std::memcmp(data, "#bundle", 8) == 0) {
        if (depth >= max_bundle_depth) {
            out.error = "bundles nested deeper than " + std::to_string(max_bundle_depth);
            return false;
        }
        if (size < 16) {
            out.error = "truncated bundle header";
            return false;
        }
        Timetag inner{read_be32(data + 8), read_be32(data + 12)};
        // A nested bundle that says "immediately" inherits its parent's time (OSC 1.0: inner times
        // must not precede outer ones, and "now" inside a timed bundle means the bundle's time).
        if (inner.immediate() && bundled) inner = tt;
        std::size_t offset = 16;
        while (offset < size) {
            if (size - offset < 4) {
                out.error = "truncated bundle element size";
                return false;
            }
            const std::uint32_t element = read_be32(data + offset);
            offset += 4;
            if (element == 0 || element % 4 != 0 || element > size - offset) {
                out.error = "bad bundle element size " + std::to_string(element);
                return false;
            }
            if (!decode_element(data + offset, element, inner, true, depth + 1, out)) return false;
            offset += element;
        }
        return true;
    }
    if (size == 0 || data[0] != '/') {
        out.error = "not an OSC message or bundle";
        return false;
    }
    return decode_message(data, size, tt, bundled, out);
}

}  // namespace

double Timetag::to_unix_seconds() const {
    return static_cast<double>(seconds) - ntp_unix_offset + static_cast<double>(fraction) * 0x1.0p-32;
}

Timetag Timetag::from_unix_seconds(double unix_seconds) {
    const double ntp = unix_seconds + ntp_unix_offset;
    const double whole = std::floor(ntp);
    return {static_cast<std::uint32_t>(whole), static_cast<std::uint32_t>((ntp - whole) * 0x1.0p32)};
}

OscArgument OscArgument::from_float(float v) {
    OscArgument a;
    a.type = 'f';
    // As typed, as decode_message reads an 'f' off the wire: an argument means the same number whether it
    // was built here or received. A text score's "/drop 3 0 0.15 0.05" (render score) otherwise put the drop
    // at x = 0.15000000596 m where ameotod, sent the same float, puts it at 0.15 m: the drop's masses round
    // differently from the first step, and the two renders of one score part in the last bits.
    a.number = float_as_typed(v);
    return a;
}
OscArgument OscArgument::from_int(std::int32_t v) {
    OscArgument a;
    a.type = 'i';
    a.integer = v;
    a.number = v;
    return a;
}
OscArgument OscArgument::from_int64(std::int64_t v) {
    OscArgument a;
    a.type = 'h';
    a.integer = v;
    a.number = static_cast<double>(v);
    return a;
}
OscArgument OscArgument::from_string(std::string v) {
    OscArgument a;
    a.type = 's';
    a.text = std::move(v);
    return a;
}

DecodedPacket decode_packet(const void* data, std::size_t size) {
    DecodedPacket out;
    if (size % 4 != 0) {
        out.error = "OSC packet size " + std::to_string(size) + " is not a multiple of 4";
        return out;
    }
    if (!decode_element(static_cast<const unsigned char*>(data), size, Timetag{}, false, 0, out)) out.messages.clear();
    return out;
}

std::vector<unsigned char> encode_message(const std::string& address, const std::vector<OscArgument>& args) {
    MessagePtr msg(lo_message_new());
    for (const auto& a : args) {
        switch (a.type) {
            case 'i': lo_message_add_int32(msg.get(), static_cast<std::int32_t>(a.integer)); break;
            case 'h': lo_message_add_int64(msg.get(), a.integer); break;
            case 'f': lo_message_add_float(msg.get(), static_cast<float>(a.number)); break;
            case 'd': lo_message_add_double(msg.get(), a.number); break;
            case 's': lo_message_add_string(msg.get(), a.text.c_str()); break;
            case 'S': lo_message_add_symbol(msg.get(), a.text.c_str()); break;
            case 'c': lo_message_add_char(msg.get(), static_cast<char>(a.integer)); break;
            case 'T': lo_message_add_true(msg.get()); break;
            case 'F': lo_message_add_false(msg.get()); break;
            case 'N': lo_message_add_nil(msg.get()); break;
            case 'I': lo_message_add_infinitum(msg.get()); break;
            default: throw std::invalid_argument(std::string("encode_message: unsupported OSC type '") + a.type + "'");
        }
    }
    std::size_t size = 0;
    void* bytes = lo_message_serialise(msg.get(), address.c_str(), nullptr, &size);
    std::vector<unsigned char> out(static_cast<unsigned char*>(bytes), static_cast<unsigned char*>(bytes) + size);
    std::free(bytes);
    return out;
}

std::vector<unsigned char> encode_bundle(Timetag timetag, const std::vector<std::vector<unsigned char>>& elements) {
    std::vector<unsigned char> out{'#', 'b', 'u', 'n', 'd', 'l', 'e', 0};
    write_be32(out, timetag.seconds);
    write_be32(out, timetag.fraction);
    for (const auto& e : elements) {
        write_be32(out, static_cast<std::uint32_t>(e.size()));
        out.insert(out.end(), e.begin(), e.end());
    }
    return out;
}

}  // namespace ameoto::protocol
