// SPDX-License-Identifier: GPL-3.0-or-later
// /listener/orientation: degrees in, radians out, on every format but ears (refused with the reason);
// its query form.

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

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
    CHECK(v.request.command.values[0] == ameoto::test::relative(M_PI / 2));
    CHECK(v.request.command.values[1] == ameoto::test::relative(-M_PI / 6));
    CHECK(v.request.command.values[2] == doctest::Approx(M_PI));
    CHECK(v.request.command.object == nullptr);   // the daemon attaches the matrix (packet_dispatch.cpp)
    CHECK_FALSE(validate(orientation(0.0f, 91.0f, 0.0f), ambisonic).ok);   // pitch past the zenith

    // Stereo and rings turn by re-panning: accepted the same way.
    ProtocolContext stereo = test::round_surface_context();
    stereo.ambisonic_order = 0;
    const Validation panned = validate(orientation(90.0f, 0.0f, 0.0f), stereo);
    REQUIRE_MESSAGE(panned.ok, panned.reason);
    CHECK(panned.request.command.kind == CommandKind::orientation);
    CHECK(panned.request.command.values[0] == ameoto::test::relative(M_PI / 2));

    // Ears: two fixed ear points under the umbrella; refused, and the reason says what does turn.
    ProtocolContext ears = stereo;
    ears.ears = true;
    const Validation refused = validate(orientation(90.0f, 0.0f, 0.0f), ears);
    CHECK_FALSE(refused.ok);
    CHECK(refused.reason.find("two ear points") != std::string::npos);
    CHECK(refused.reason.find("stereo, ring:N, ambix:N or binaural") != std::string::npos);
}

TEST_CASE("/listener/orientation with no value is its query; two values are neither") {
    const ProtocolContext stereo;
    DecodedMessage m;
    m.address = "/listener/orientation";
    const Validation q = validate(m, stereo);
    REQUIRE_MESSAGE(q.ok, q.reason);
    CHECK(q.request.action == Action::query);
    CHECK(q.request.query_address == "/listener/orientation");
    m.types = "ff";
    m.args = {OscArgument::from_float(1.0f), OscArgument::from_float(2.0f)};
    CHECK_FALSE(validate(m, stereo).ok);
}
