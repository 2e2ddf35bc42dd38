// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/argument_types.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ameoto::client {
namespace {

using protocol::OscArgument;

// std::from_chars refuses a leading '+', which people do type ("+3").
std::string_view without_plus(std::string_view word) {
    if (word.size() > 1 && word[0] == '+' && word[1] != '-' && word[1] != '+') word.remove_prefix(1);
    return word;
}

bool parse_int64(std::string_view word, std::int64_t& out) {
    word = without_plus(word);
    const auto r = std::from_chars(word.data(), word.data() + word.size(), out);
    return !word.empty() && r.ec == std::errc() && r.ptr == word.data() + word.size();
}

bool is_integer_literal(std::string_view word) {
    word = without_plus(word);
    if (!word.empty() && word[0] == '-') word.remove_prefix(1);
    if (word.empty()) return false;
    for (char c : word)
        if (c < '0' || c > '9') return false;
    return true;
}

// Decimal numbers only: from_chars(general) takes "1e3", ".5", "inf", "nan", not hex.
bool parse_double(std::string_view word, double& out) {
    word = without_plus(word);
    const auto r = std::from_chars(word.data(), word.data() + word.size(), out, std::chars_format::general);
    return !word.empty() && r.ec == std::errc() && r.ptr == word.data() + word.size();
}

bool fits_float(double v) { return !std::isfinite(v) || std::abs(v) <= std::numeric_limits<float>::max(); }

OscArgument make_double(double v) {
    OscArgument a;
    a.type = 'd';
    a.number = v;
    return a;
}

OscArgument make_bool(bool v) {
    OscArgument a;
    a.type = v ? 'T' : 'F';
    a.number = v ? 1 : 0;
    return a;
}

// Built by appending: GCC 12 warns falsely (-Wrestrict, bug 105329) on "'" + std::string(...).
std::string quoted(std::string_view word) {
    std::string out = "'";
    out.append(word);
    out += '\'';
    return out;
}

}  // namespace

OscArgument infer_argument(std::string_view word) {
    if (is_integer_literal(word)) {
        std::int64_t n = 0;
        if (parse_int64(word, n)) {
            if (n >= std::numeric_limits<std::int32_t>::min() && n <= std::numeric_limits<std::int32_t>::max())
                return OscArgument::from_int(static_cast<std::int32_t>(n));
            return OscArgument::from_int64(n);
        }
        // Too long even for 64 bits: still a number to the user, so send it as one.
        double d = 0;
        if (parse_double(word, d)) return make_double(d);
    }
    if (word.find_first_of(".eE") != std::string_view::npos) {
        double d = 0;
        // "inf" and "nan" carry no '.' or exponent and so stay strings; "infinite" has an 'e' but
        // does not parse fully, so it stays a string too.
        if (parse_double(word, d) && std::isfinite(d)) return fits_float(d) ? OscArgument::from_float(static_cast<float>(d)) : make_double(d);
    }
    if (word == "true") return make_bool(true);
    if (word == "false") return make_bool(false);
    return OscArgument::from_string(std::string(word));
}

TypedArguments inferred_arguments(const std::vector<std::string>& words) {
    TypedArguments t;
    for (const auto& w : words) t.arguments.push_back(infer_argument(w));
    return t;
}

TypedArguments typed_arguments(std::string_view types, const std::vector<std::string>& words) {
    TypedArguments t;
    if (!types.empty() && types[0] == ',') types.remove_prefix(1);
    if (types.size() != words.size()) {
        t.error = "--types '" + std::string(types) + "' has " + std::to_string(types.size()) + " type" +
                  (types.size() == 1 ? "" : "s") + " but " + std::to_string(words.size()) + " argument" +
                  (words.size() == 1 ? " was" : "s were") + " given";
        return t;
    }
    for (std::size_t i = 0; i < words.size(); ++i) {
        const std::string& w = words[i];
        const char type = types[i];
        const std::string where = "argument " + std::to_string(i + 1) + " " + quoted(w) + ": ";
        auto fail = [&](const std::string& why) {
            t.arguments.clear();
            t.error = where + why;
            return t;
        };
        std::int64_t n = 0;
        double d = 0;
        switch (type) {
            case 'i':
                if (!parse_int64(w, n)) return fail("is not an integer (type i)");
                if (n < std::numeric_limits<std::int32_t>::min() || n > std::numeric_limits<std::int32_t>::max())
                    return fail("does not fit a 32-bit integer (type i; use h for 64 bits)");
                t.arguments.push_back(OscArgument::from_int(static_cast<std::int32_t>(n)));
                break;
            case 'h':
                if (!parse_int64(w, n)) return fail("is not a 64-bit integer (type h)");
                t.arguments.push_back(OscArgument::from_int64(n));
                break;
            case 'f':
                if (!parse_double(w, d)) return fail("is not a number (type f)");
                if (!fits_float(d)) return fail("does not fit a 32-bit float (type f; use d for 64 bits)");
                t.arguments.push_back(OscArgument::from_float(static_cast<float>(d)));
                break;
            case 'd':
                if (!parse_double(w, d)) return fail("is not a number (type d)");
                t.arguments.push_back(make_double(d));
                break;
            case 's':
                t.arguments.push_back(OscArgument::from_string(w));
                break;
            case 'T':
            case 'F': {
                const bool want = type == 'T';
                if (w != (want ? "true" : "false")) return fail(std::string("type ") + type + " needs the word " + (want ? "true" : "false"));
                t.arguments.push_back(make_bool(want));
                break;
            }
            default:
                return fail(std::string("unsupported type '") + type + "' (use i h f d s T F)");
        }
    }
    return t;
}

}  // namespace ameoto::client
