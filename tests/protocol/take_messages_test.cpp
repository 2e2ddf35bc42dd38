// SPDX-License-Identifier: GPL-3.0-or-later
// A take's messages (protocol/take_messages.hpp) come back from their bytes exactly as written: the
// doubles bit for bit, the frame as an integer, the scene text with its newlines; the size prefix and
// the timetag are scsynth's score format; malformed records are refused with the reason.
#include "protocol/take_messages.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "engine/scene/scene_description.hpp"

using namespace ameoto;
using namespace ameoto::protocol;

namespace {

// The one message of a size-prefixed take element, decoded as a score reader decodes it.
DecodedMessage decoded_element(const std::vector<unsigned char>& element) {
    REQUIRE(element.size() > 4);
    const std::uint32_t size = (std::uint32_t{element[0]} << 24) | (std::uint32_t{element[1]} << 16) | (std::uint32_t{element[2]} << 8) | element[3];
    REQUIRE(size == element.size() - 4);
    REQUIRE(std::memcmp(element.data() + 4, "#bundle", 8) == 0);
    const DecodedPacket p = decode_packet(element.data() + 4, size);
    REQUIRE_MESSAGE(p.error.empty(), p.error);
    REQUIRE(p.messages.size() == 1);
    return p.messages[0];
}

}  // namespace

TEST_CASE("take messages: start, command, scene and frames come back exactly; the timetag is the frame's time") {
    TakeStart start;
    start.rate_hz = 44100.0;
    start.channels = 3;
    start.seed = 0xfedcba9876543210ull;   // past int64's range: carried by its bits
    start.node = 2;
    start.limiter = true;
    start.level_gain_db = 17.123456789012345;
    start.adaptive_detail = true;
    start.scene = format_scene(*builtin_scene("forest"));
    start.format = "ambix:1";
    TakeStart s2;
    REQUIRE(read_take_start(decoded_element(take_element(0, 44100.0, take_start_address, take_start_arguments(start))), s2).empty());
    CHECK(s2.rate_hz == start.rate_hz);
    CHECK(s2.channels == 3);
    CHECK(s2.seed == start.seed);
    CHECK(s2.node == 2);
    CHECK(s2.limiter);
    CHECK(s2.level_gain_db == start.level_gain_db);
    CHECK(s2.adaptive_detail);
    CHECK(s2.scene == start.scene);
    CHECK(s2.format == "ambix:1");
    // A format-1 take (before the output format was recorded): its ten arguments, read with no format.
    std::vector<OscArgument> old = take_start_arguments(start);
    old[0] = OscArgument::from_int(1);
    old.pop_back();
    TakeStart s1;
    REQUIRE(read_take_start(decoded_element(take_element(0, 44100.0, take_start_address, old)), s1).empty());
    CHECK(s1.format.empty());
    CHECK(s1.channels == 3);
    CHECK(s1.scene == start.scene);

    Command c;
    c.kind = CommandKind::drop;
    c.values[0] = 0.1 * 0.03;   // not a short decimal: every bit must survive
    c.values[1] = 0.0;
    c.values[2] = 1.0 / 3.0;
    c.values[3] = -2e-17;
    const DecodedMessage m = decoded_element(take_element(123457, 48000.0, take_command_address, take_command_arguments(123457, c)));
    CHECK(m.bundled);
    // 123457 / 48000 s as OSC's 32.32 fixed point, seconds from the start (no 1900 epoch).
    CHECK(m.timetag.seconds == 2);
    CHECK(std::fabs(m.timetag.fraction / 4294967296.0 - (123457.0 / 48000.0 - 2.0)) < 1e-9);
    std::uint64_t frame = 0;
    Command back;
    REQUIRE(read_take_command(m, frame, back).empty());
    CHECK(frame == 123457);
    CHECK(back.kind == CommandKind::drop);
    for (int k = 0; k < 4; ++k) CHECK(std::memcmp(&back.values[k], &c.values[k], sizeof(double)) == 0);

    TakeSceneChange change;
    change.frame = 96000;
    change.kind = CommandKind::swap_surface;
    change.material = MembraneMaterial::nylon_canopy();
    change.material.name = "custom-1";
    change.material.tension = 777.25;
    change.liquid = liquids::milk();
    TakeSceneChange c2;
    REQUIRE(read_take_scene(decoded_element(take_element(96000, 48000.0, take_scene_address, take_scene_arguments(change))), c2).empty());
    CHECK(c2.frame == 96000);
    CHECK(c2.kind == CommandKind::swap_surface);
    CHECK(c2.material.name == "custom-1");
    CHECK(c2.material.tension == 777.25);
    CHECK(c2.material.stiffness_damping == change.material.stiffness_damping);
    CHECK(c2.liquid.name == change.liquid.name);
    CHECK(c2.liquid.viscosity == change.liquid.viscosity);

    std::uint64_t frames = 0, lost = 0;
    REQUIRE(read_take_frames(decoded_element(take_element(5000, 48000.0, take_frames_address, take_frames_arguments(5000, 3))), frames, lost).empty());
    CHECK(frames == 5000);
    CHECK(lost == 3);
    // Frame 0 is not OSC's "immediately" ({0, 1}): a score reader would otherwise play it at once.
    CHECK_FALSE(decoded_element(take_element(0, 48000.0, take_frames_address, take_frames_arguments(0, 0))).timetag.immediate());
}

TEST_CASE("take messages: a record of the wrong shape, kind or version is refused with the reason") {
    Command sync;
    sync.kind = CommandKind::sync;
    std::uint64_t frame = 0;
    Command c;
    CHECK(read_take_command(decoded_element(take_element(1, 48000.0, take_command_address, take_command_arguments(1, sync))), frame, c) ==
          "command kind 2 is not one a take records as a command");
    DecodedMessage short_one = decoded_element(take_element(1, 48000.0, take_command_address, {OscArgument::from_int64(1)}));
    CHECK(read_take_command(short_one, frame, c) == "1 arguments, not the 6 of take format 2");
    TakeStart start;
    std::vector<OscArgument> args = take_start_arguments(start);
    args[0] = OscArgument::from_int(99);
    TakeStart s2;
    CHECK(read_take_start(decoded_element(take_element(0, 48000.0, take_start_address, args)), s2) == "take format 99: this ameoto reads formats 1 and 2");
    args = take_start_arguments(start);
    args[2] = OscArgument::from_int(40);
    CHECK(read_take_start(decoded_element(take_element(0, 48000.0, take_start_address, args)), s2) == "channels 40 is not 1..16");
    args = take_start_arguments(start);
    args[9] = OscArgument::from_int(1);
    CHECK(read_take_start(decoded_element(take_element(0, 48000.0, take_start_address, args)), s2) == "argument 10 should be a string");
    args = take_start_arguments(start);
    args[10] = OscArgument::from_string("");
    CHECK(read_take_start(decoded_element(take_element(0, 48000.0, take_start_address, args)), s2) ==
          "the output format is empty (\"stereo\", \"ambix:1\", \"binaural\", ...)");
    Command turn;   // /listener/orientation: recorded as a command since take format 2
    turn.kind = CommandKind::orientation;
    turn.values[0] = 1.5707963267948966;
    CHECK(read_take_command(decoded_element(take_element(5, 48000.0, take_command_address, take_command_arguments(5, turn))), frame, c).empty());
    CHECK(c.kind == CommandKind::orientation);
    CHECK(c.values[0] == turn.values[0]);
}
