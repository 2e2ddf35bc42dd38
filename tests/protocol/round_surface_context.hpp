// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The ProtocolContext the protocol tests validate against: every surface a disc of radius 0.5 m about
// the origin, so that a /drop's (x, y) lands on it or not by a rule a test can see.
//
// Interface:
//   validate(message, round_surface_context());

#include <string>

#include "protocol/address_table.hpp"

namespace ameoto::test {

inline protocol::ProtocolContext round_surface_context() {
    protocol::ProtocolContext c;
    c.on_surface = [](const std::string&, double x, double y) { return x * x + y * y <= 0.25; };
    c.ambisonic_order = 1;   // an Ambisonic stream (first order)

    return c;
}

}  // namespace ameoto::test
