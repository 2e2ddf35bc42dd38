// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One-letter OSC arguments for tests that spell out many messages: f(0.5) for a float, i(3) for an
// int32, s("pond") for a string, as OSC's own type tags name them. One definition for every suite, so
// that test files built together (CMake's unity build) cannot clash.
//
// Interface (bring them in with `using namespace ameoto::test::osc_shorthand;`):
//   f(double) -> a float32 argument; d(double) -> a float64; i(int) -> an int32; s(string) -> a string
//   message(address, {args...}) -> a DecodedMessage as the codec would hand it over (type tags filled in)

#include <string>
#include <utility>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::test::osc_shorthand {

inline protocol::OscArgument f(double v) { return protocol::OscArgument::from_float(static_cast<float>(v)); }
inline protocol::OscArgument d(double v) {
    protocol::OscArgument a;
    a.type = 'd';
    a.number = v;
    return a;
}
inline protocol::OscArgument i(int v) { return protocol::OscArgument::from_int(v); }
inline protocol::OscArgument s(const std::string& v) { return protocol::OscArgument::from_string(v); }

inline protocol::DecodedMessage message(const std::string& address, std::vector<protocol::OscArgument> args = {}) {
    protocol::DecodedMessage m;
    m.address = address;
    m.args = std::move(args);
    for (const auto& a : m.args) m.types += a.type;
    return m;
}

}  // namespace ameoto::test::osc_shorthand
