// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto render score TAKE`, where TAKE is a recording in ameotod's --record-score format
// (protocol/take_messages.hpp): the commands at their recorded samples give the samples a score of the
// same messages gives; a take cut mid-write renders up to its last whole record; a take's own setup
// cannot be overridden; a malformed record refuses it with where and why. The full round trip (a live
// paced stream recorded and rendered again) is tests/integration/record_score_test.cpp.
#include "clients/ameoto/render_score.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/render_drop.hpp"
#include "engine/scene/scene_description.hpp"
#include "protocol/address_table.hpp"
#include "protocol/take_messages.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace ameoto;
using namespace ameoto::client;
using protocol::OscArgument;

namespace {

int render_words(const std::vector<std::string>& words, std::string& out, std::string& err) {
    std::ostringstream o, e;
    const CommandIo io{{}, o, e};
    const int status = run_render(words, io);
    out = o.str();
    err = e.str();
    return status;
}

// A message as ameotod validates it, to the SI command the engine gets.
Command validated(const std::string& address, const std::vector<OscArgument>& args, int ambisonic_order = 0) {
    protocol::DecodedMessage m;
    m.address = address;
    m.args = args;
    for (const OscArgument& a : args) m.types += a.type;
    protocol::ProtocolContext context;
    context.on_surface = [](const std::string&, double, double) { return true; };
    context.ambisonic_order = ambisonic_order;   // an ambix:N stream's (/listener/orientation)
    const protocol::Validation v = protocol::validate(m, context);
    REQUIRE_MESSAGE(v.ok, v.reason);
    return v.request.command;
}

struct TakeBytes {
    std::vector<unsigned char> bytes;
    void add(std::uint64_t frame, const char* address, const std::vector<OscArgument>& args) {
        const auto e = protocol::take_element(frame, 48000.0, address, args);
        bytes.insert(bytes.end(), e.begin(), e.end());
    }
    std::string write(const std::string& name) const {
        const std::string path = ameoto::test::temp_path(name);
        std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        return path;
    }
};

// The umbrella at rain 0, seed 9; a drop at 0.013 s, rain 40 mm/h at 0.1 s, a wind at 0.2 s (frames at 48 kHz).
TakeBytes three_commands() {
    TakeBytes t;
    protocol::TakeStart start;
    start.seed = 9;
    SceneDescription scene = *builtin_scene("umbrella");
    scene.rain.rate_mm_per_h = 0.0;
    start.scene = format_scene(scene);
    t.add(0, protocol::take_start_address, protocol::take_start_arguments(start));
    const auto f = [](float v) { return OscArgument::from_float(v); };
    t.add(624, protocol::take_command_address, protocol::take_command_arguments(624, validated("/drop", {f(3), f(0), f(0.15f), f(0.05f)})));
    t.add(4800, protocol::take_command_address, protocol::take_command_arguments(4800, validated("/rain/rate", {f(40)})));
    t.add(9600, protocol::take_command_address, protocol::take_command_arguments(9600, validated("/rain/wind", {f(5), f(90), f(0.3f)})));
    return t;
}

}  // namespace

TEST_CASE("render score of a take: its commands at their recorded samples, the samples a score of the same messages renders") {
    TakeBytes take = three_commands();
    take.add(19200, protocol::take_end_address, protocol::take_frames_arguments(19200, 0));
    const std::string take_path = take.write("three.take");
    const std::string score = ameoto::test::temp_path("three.txt");
    std::ofstream(score) << "0.013 /drop 3 0 0.15 0.05\n0.1 /rain/rate 40\n0.2 /rain/wind 5 90 0.3\n";
    const std::string a = ameoto::test::temp_path("three-take.wav"), b = ameoto::test::temp_path("three-score.wav");
    std::string out, err;
    REQUIRE_MESSAGE(render_words({"score", take_path, "-o", a, "--block", "61", "--quiet"}, out, err) == exit_status::ok, err);
    CHECK(out.find("3 commands, 0 scene changes, fixed detail as live") != std::string::npos);
    REQUIRE(render_words({"score", score, "-o", b, "--rain", "0", "--seed", "9", "--seconds", "0.4", "--quiet"}, out, err) == exit_status::ok);
    const auto wa = ameoto::test::read_wav(a), wb = ameoto::test::read_wav(b);
    REQUIRE(wa.ok);
    REQUIRE(wb.ok);
    CHECK(wa.frames == 19200);   // the take's /take/end
    CHECK(wa.samples == wb.samples);
    // Its setup is its own.
    CHECK(render_words({"score", take_path, "-o", a, "--seed", "3"}, out, err) == exit_status::usage);
    CHECK(err.find("is a recorded take: it names its own scene, rain, rate, seed and output format (--seed cannot change them)") != std::string::npos);
}

TEST_CASE("render score of a take cut mid-write (ameotod killed): up to its last whole record; a malformed record refuses it") {
    TakeBytes take = three_commands();
    take.add(9600, protocol::take_frames_address, protocol::take_frames_arguments(9600, 0));
    TakeBytes full = take;
    full.add(19200, protocol::take_end_address, protocol::take_frames_arguments(19200, 0));
    const std::vector<unsigned char> tail = protocol::take_element(12000, 48000.0, protocol::take_frames_address,
                                                                   protocol::take_frames_arguments(12000, 0));
    take.bytes.insert(take.bytes.end(), tail.begin(), tail.begin() + 7);   // a bundle cut after 7 of its bytes
    const std::string cut = take.write("cut.take"), whole = full.write("whole.take");
    const std::string a = ameoto::test::temp_path("cut.wav"), b = ameoto::test::temp_path("whole.wav");
    std::string out, err;
    REQUIRE_MESSAGE(render_words({"score", cut, "-o", a, "--quiet"}, out, err) == exit_status::ok, err);
    CHECK(err.find("the take was not closed") != std::string::npos);
    REQUIRE(render_words({"score", whole, "-o", b, "--quiet"}, out, err) == exit_status::ok);
    const auto wa = ameoto::test::read_wav(a), wb = ameoto::test::read_wav(b);
    REQUIRE(wa.ok);
    REQUIRE(wb.ok);
    CHECK(wa.frames == 9600);   // its last /take/frames
    REQUIRE(wb.frames == 19200);
    CHECK(std::equal(wa.samples.begin(), wa.samples.end(), wb.samples.begin()));

    // A record that is no command a take holds (kind 2, /sync) names where it is and why; nothing written.
    TakeBytes bad = three_commands();
    Command sync;
    sync.kind = CommandKind::sync;
    bad.add(700, protocol::take_command_address, protocol::take_command_arguments(700, sync));
    const std::string bad_path = bad.write("bad.take");
    const std::string c = ameoto::test::temp_path("bad-take.wav");
    std::filesystem::remove(c);
    CHECK(render_words({"score", bad_path, "-o", c, "--quiet"}, out, err) == exit_status::refused);
    CHECK(err.find("bad.take: bundle 5, message 1: /take/command: command kind 2 is not one a take records as a command") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(c));
}

TEST_CASE("render score of an ambix:1 take: in its own format, the head's turn at its sample, as a score with --format ambix:1") {
    // Take format 2 names the output format; /listener/orientation is a recorded command (take_messages.hpp).
    TakeBytes take;
    protocol::TakeStart start;
    start.seed = 9;
    start.channels = 4;
    start.format = "ambix:1";
    SceneDescription scene = *builtin_scene("umbrella");
    scene.rain.rate_mm_per_h = 0.0;
    start.scene = format_scene(scene);
    take.add(0, protocol::take_start_address, protocol::take_start_arguments(start));
    const auto f = [](float v) { return OscArgument::from_float(v); };
    take.add(624, protocol::take_command_address, protocol::take_command_arguments(624, validated("/drop", {f(3), f(0), f(0.15f), f(0.05f)})));
    take.add(4800, protocol::take_command_address,
             protocol::take_command_arguments(4800, validated("/listener/orientation", {f(90), f(10), f(0)}, 1)));
    take.add(9600, protocol::take_command_address, protocol::take_command_arguments(9600, validated("/drop", {f(4), f(0), f(-0.2f), f(0)})));
    take.add(19200, protocol::take_end_address, protocol::take_frames_arguments(19200, 0));
    const std::string take_path = take.write("ambix.take");
    const std::string score = ameoto::test::temp_path("ambix-turn.txt");
    std::ofstream(score) << "0.013 /drop 3 0 0.15 0.05\n0.1 /listener/orientation 90 10 0\n0.2 /drop 4 0 -0.2 0\n";
    const std::string a = ameoto::test::temp_path("ambix-take.wav"), b = ameoto::test::temp_path("ambix-score.wav");
    std::string out, err;
    REQUIRE_MESSAGE(render_words({"score", take_path, "-o", a, "--quiet"}, out, err) == exit_status::ok, err);
    CHECK(out.find("3 commands, 0 scene changes") != std::string::npos);
    REQUIRE_MESSAGE(render_words({"score", score, "-o", b, "--rain", "0", "--seed", "9", "--seconds", "0.4", "--format", "ambix:1", "--quiet"},
                                 out, err) == exit_status::ok,
                    err);
    const auto wa = ameoto::test::read_wav(a), wb = ameoto::test::read_wav(b);
    REQUIRE(wa.ok);
    REQUIRE(wb.ok);
    CHECK(wa.channels == 4);
    CHECK(wa.frames == 19200);
    CHECK(wa.samples == wb.samples);
    // A take whose format and channels disagree is refused, with both named.
    start.channels = 2;
    TakeBytes wrong;
    wrong.add(0, protocol::take_start_address, protocol::take_start_arguments(start));
    wrong.add(4800, protocol::take_end_address, protocol::take_frames_arguments(4800, 0));
    CHECK(render_words({"score", wrong.write("wrong.take"), "-o", a, "--quiet"}, out, err) == exit_status::refused);
    CHECK(err.find("/take/start: 2 channels, but ambix:1 has 4") != std::string::npos);
}
