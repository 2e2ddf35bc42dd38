// SPDX-License-Identifier: GPL-3.0-or-later
// /listener/orientation: degrees in, radians out, on an Ambisonic stream; refused with the reason on others.

#include <doctest/doctest.h>

#include <cmath>

#include "protocol/address_table.hpp"
#include "protocol/osc_codec.hpp"
#include "tests/protocol/round_surface_context.hpp"

using namespace ameoto;
using namespace ameoto::protocol;

namespace {
DecodedMessage orientation(float yaw, float pitch, float roll) {
    DecodedMessage m;
    m.address = "/listener/orientation";
    m.types = "fff";
    for (float v : {yaw, pitch, roll}) m.args.push_back(OscArgument::from_float(v));
    return m;
}
}  // namespace

TEST_CASE("/listener/orientation: an Ambisonic stream gets the head's yaw, pitch and roll in radians") {
    ProtocolContext ambisonic = test::round_surface_context();
    ambisonic.ambisonic_order = 3;
    const Validation v = validate(orientation(90.0f, -30.0f, 180.0f), ambisonic);
    REQUIRE_MESSAGE(v.ok, v.reason);
    CHECK(v.request.action == Action::enqueue);
    CHECK(v.request.command.kind == CommandKind::orientation);
    CHECK(v.request.command.values[0] == doctest::Approx(M_PI / 2));
    CHECK(v.request.command.values[1] == doctest::Approx(-M_PI / 6));
    CHECK(v.request.command.values[2] == doctest::Approx(M_PI));
    CHECK(v.request.command.object == nullptr);   // the daemon attaches the matrix (packet_dispatch.cpp)
    CHECK_FALSE(validate(orientation(0.0f, 91.0f, 0.0f), ambisonic).ok);   // pitch past the zenith

    ProtocolContext stereo = test::round_surface_context();
    stereo.ambisonic_order = 0;
    const Validation refused = validate(orientation(90.0f, 0.0f, 0.0f), stereo);
    CHECK_FALSE(refused.ok);
    CHECK(refused.reason.find("Ambisonic stream only") != std::string::npos);
}
