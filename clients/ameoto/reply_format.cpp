// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/reply_format.hpp"

#include <array>
#include <charconv>
#include <cstdio>

namespace ameoto::client {
namespace {

template <typename T>
std::string shortest(T value) {
    std::array<char, 64> buffer{};
    const auto r = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), r.ptr);
}

// "48000" -> "48000.0", so a float never reads as an integer; "1e+20", "inf", "nan" stay as they are.
std::string as_float_text(std::string text) {
    if (text.find_first_not_of("-0123456789") == std::string::npos) text += ".0";
    return text;
}

std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (const unsigned char c : text) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            case '\r': out += "\\r"; break;
            default:
                if (c < 0x20 || c == 0x7f) {
                    char hex[8];
                    std::snprintf(hex, sizeof hex, "\\x%02x", c);
                    out += hex;
                } else {
                    out += static_cast<char>(c);
                }
        }
    }
    return out + "\"";
}

}  // namespace

std::string shortest_float(float value) { return shortest(value); }
std::string shortest_double(double value) { return shortest(value); }

std::string format_argument(const protocol::OscArgument& a) {
    switch (a.type) {
        case 'i':
        case 'h': return std::to_string(a.integer);
        case 'f': return as_float_text(shortest_float(static_cast<float>(a.number)));
        case 'd': return as_float_text(shortest_double(a.number));
        case 's':
        case 'S': return quoted(a.text);
        case 'c': return {'\'', static_cast<char>(a.integer), '\''};
        case 'T': return "true";
        case 'F': return "false";
        case 'N': return "nil";
        case 'I': return "infinitum";
        // The codec keeps these by type only (protocol/osc_codec.hpp); the server sends none.
        case 'b': return "<blob>";
        case 'm': return "<midi>";
        case 't': return "<timetag>";
        default: return {'<', 't', 'y', 'p', 'e', ' ', a.type, '>'};
    }
}

std::string format_message(const protocol::DecodedMessage& message) {
    std::string line = message.address;
    for (const auto& a : message.args) {
        line += ' ';   // appended apart: GCC 12 warns falsely (-Wrestrict) on " " + std::string
        line += format_argument(a);
    }
    return line;
}

}  // namespace ameoto::client
