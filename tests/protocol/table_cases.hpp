// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Messages made from the protocol table itself (protocol::address_table()), for the tests that walk
// the whole address space: a valid message for each address, and for each the bad variants every
// address must refuse. A new address in the table gets all of them without a line of test code.
// Header only: the unit test (tests/protocol), the UDP test (tests/integration) and the fuzz corpus
// maker (tests/fuzz) share it.
//
// Interface:
//   std::vector<OscArgument> args = valid_arguments(spec);        // required arguments, valid values
//   for (const BadCase& c : bad_cases(spec)) ... c.what, c.args   // each must be refused
//   std::vector<BadPacket> p = bad_packets();                      // malformed and too-deep bundles, ...

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "protocol/address_table.hpp"
#include "protocol/osc_codec.hpp"

namespace ameoto::test {

using protocol::ArgumentKind;
using protocol::ArgumentSpec;
using protocol::OscArgument;

// A value every argument of its kind accepts: the text's example, or the middle of the range
// (integers rounded down). Within range by construction, so only the variant makes a message bad.
inline OscArgument valid_argument(const ArgumentSpec& a) {
    if (a.kind == ArgumentKind::text) return OscArgument::from_string(a.example);
    const double middle = std::floor(0.5 * (a.min + a.max));
    if (a.kind == ArgumentKind::integer) return OscArgument::from_int(static_cast<std::int32_t>(middle));
    OscArgument v;
    v.type = 'd';
    v.number = 0.5 * (a.min + a.max);
    return v;
}

inline std::vector<OscArgument> valid_arguments(const protocol::AddressSpec& spec, bool with_optional = false) {
    std::vector<OscArgument> args;
    for (const ArgumentSpec& a : spec.arguments)
        if (!a.optional || with_optional) args.push_back(valid_argument(a));
    return args;
}

inline OscArgument double_argument(double v) {
    OscArgument a;
    a.type = 'd';
    a.number = v;
    return a;
}

struct BadCase {
    std::string what;                  // for the test's message: "argument 2 (speed): NaN"
    std::vector<OscArgument> args;
    bool refused_by_scene = false;     // a text the table passes on and the scene check refuses
};

// For each argument (optional ones after valid values for those before): wrong types, NaN, Inf,
// huge, negative and just-outside values, non-integers, overlong and path-like strings; then a
// missing and an extra argument.
inline std::vector<BadCase> bad_cases(const protocol::AddressSpec& spec) {
    std::vector<BadCase> cases;
    const std::vector<OscArgument> all = valid_arguments(spec, true);
    for (std::size_t i = 0; i < spec.arguments.size(); ++i) {
        const ArgumentSpec& a = spec.arguments[i];
        const std::string where = "argument " + std::to_string(i + 1) + " (" + a.name + "): ";
        auto with = [&](const std::string& what, OscArgument v, bool by_scene = false) {
            std::vector<OscArgument> args(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(i));
            args.push_back(std::move(v));
            cases.push_back({where + what, std::move(args), by_scene});
        };
        OscArgument nil;
        nil.type = 'N';
        OscArgument yes;
        yes.type = 'T';
        with("nil", nil);
        with("true", yes);
        if (a.kind == ArgumentKind::text) {
            with("a float", OscArgument::from_float(1.0f));
            with("an int", OscArgument::from_int(1));
            with("256 characters", OscArgument::from_string(std::string(256, 'a')));
            with("4000 characters", OscArgument::from_string(std::string(4000, 'a')));
            // Not refused by the table for a surface's material: the edited scene's check refuses it.
            const bool by_scene = std::string(a.name) == "material" && std::string(spec.address).rfind("/surface/", 0) == 0;
            with("a path", OscArgument::from_string("../../etc/passwd"), by_scene);
            with("an absolute path", OscArgument::from_string("/tmp/x"), by_scene);
            with("an empty string", OscArgument::from_string(""), by_scene);
            continue;
        }
        with("a string", OscArgument::from_string("1"));
        with("NaN (float)", OscArgument::from_float(std::numeric_limits<float>::quiet_NaN()));
        with("NaN (double)", double_argument(std::numeric_limits<double>::quiet_NaN()));
        with("+Inf", double_argument(std::numeric_limits<double>::infinity()));
        with("-Inf", OscArgument::from_float(-std::numeric_limits<float>::infinity()));
        with("huge (1e300)", double_argument(1e300));
        with("huge negative (-1e300)", double_argument(-1e300));
        with("largest int64", OscArgument::from_int64(std::numeric_limits<std::int64_t>::max()));
        if (a.max < 2147483647.0) with("largest int32", OscArgument::from_int(std::numeric_limits<std::int32_t>::max()));
        with("just above the maximum", double_argument(std::nextafter(a.max, 1e308)));
        with("just below the minimum", double_argument(std::nextafter(a.min, -1e308)));
        if (a.min > -1.0) with("negative (-1)", double_argument(-1.0));
        if (a.kind == ArgumentKind::integer) with("not an integer", double_argument(std::floor(0.5 * (a.min + a.max)) + 0.5));
    }
    const std::vector<OscArgument> required = valid_arguments(spec);
    // Without its last required argument a settable address may be its own query (docs/PROTOCOL.md,
    // "Queries": no value, or only the name of the thing asked about), which is valid, not missing.
    const bool is_query_form = spec.query.available && required.size() - 1 == spec.query.arguments.size();
    if (!required.empty() && !is_query_form)
        cases.push_back({"missing the last required argument", {required.begin(), required.end() - 1}});
    std::vector<OscArgument> extra = all;
    extra.push_back(OscArgument::from_int(1));
    cases.push_back({"an extra argument", extra});
    return cases;
}

struct BadPacket {
    std::string what;
    std::vector<unsigned char> bytes;
};

inline std::vector<unsigned char> nested_bundle(int depth, const std::vector<unsigned char>& inner) {
    std::vector<unsigned char> b = inner;
    for (int d = 0; d < depth; ++d) b = protocol::encode_bundle(protocol::Timetag{}, {b});
    return b;
}

// Packets that must not decode: each is refused whole with one /fail and changes nothing.
inline std::vector<BadPacket> bad_packets() {
    const auto rate = protocol::encode_message("/rain/rate", {OscArgument::from_float(400.0f)});
    std::vector<BadPacket> p;
    p.push_back({"bundles nested one deeper than the bound", nested_bundle(protocol::max_bundle_depth + 1, rate)});
    p.push_back({"bundles nested 100 deep", nested_bundle(100, rate)});
    {
        auto b = protocol::encode_bundle(protocol::Timetag{}, {rate});
        b[19] = 0xff;   // the element's size says more than the bundle holds
        p.push_back({"a bundle element longer than the bundle", b});
    }
    {
        auto b = protocol::encode_bundle(protocol::Timetag{}, {rate});
        b[19] = 6;      // not a multiple of 4
        p.push_back({"a bundle element size not a multiple of 4", b});
    }
    {
        auto b = protocol::encode_bundle(protocol::Timetag{}, {rate});
        b.resize(16 + 2);
        b.resize(20, 0);   // a zero-size element
        p.push_back({"a bundle with a zero-size element", b});
    }
    p.push_back({"a bundle header cut short", {'#', 'b', 'u', 'n', 'd', 'l', 'e', 0, 0, 0, 0, 0}});
    {
        auto m = rate;
        m.resize(m.size() - 4);   // the float cut off
        p.push_back({"a message cut short", m});
    }
    {
        auto m = rate;
        m.push_back(0);   // not a multiple of 4
        p.push_back({"a size not a multiple of 4", m});
    }
    {
        auto m = rate;
        m[12] = 'q';   // ",f" -> ",q": a type tag OSC does not define
        p.push_back({"an unknown type tag", m});
    }
    {
        std::vector<unsigned char> m{'/', 'r', 'a', 'i', 'n'};   // an address without its terminator
        m.resize(8, 'x');
        p.push_back({"an unterminated address", m});
    }
    p.push_back({"not OSC at all", {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd', '!'}});
    p.push_back({"a bad message inside a good bundle",
                 protocol::encode_bundle(protocol::Timetag{}, {rate, std::vector<unsigned char>{'/', 'x', 0, 0, ',', 'f', 0, 0}})});
    return p;
}

}  // namespace ameoto::test
