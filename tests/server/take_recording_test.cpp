// SPDX-License-Identifier: GPL-3.0-or-later
// --record-score's writer (server/take_recording.hpp) over a real AudioBridge: each command is recorded
// at the sample the renderer applied it (an untimed or late one at its block's first sample, a future
// one at its timetag's), /sync not at all, a noted scene change at the block that took it, and the file
// ends with /take/frames and /take/end at the frames played.
#include "server/take_recording.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <iterator>

#include "server/scene_manager.hpp"
#include "tests/support/temp_dir.hpp"

using namespace ameoto;

namespace {

// The file's messages, each with the frame its record names (its first argument; 0 for /take/start).
std::vector<protocol::DecodedMessage> read_take(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::vector<protocol::DecodedMessage> out;
    std::size_t at = 0;
    while (at + 4 <= bytes.size()) {
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at);
        const std::size_t size = (std::size_t{p[0]} << 24) | (std::size_t{p[1]} << 16) | (std::size_t{p[2]} << 8) | p[3];
        REQUIRE(at + 4 + size <= bytes.size());
        const protocol::DecodedPacket packet = protocol::decode_packet(bytes.data() + at + 4, size);
        REQUIRE_MESSAGE(packet.error.empty(), packet.error);
        out.insert(out.end(), packet.messages.begin(), packet.messages.end());
        at += 4 + size;
    }
    CHECK(at == bytes.size());
    return out;
}

Command drop_command(bool timed, std::uint64_t frame) {
    Command c;
    c.kind = CommandKind::drop;
    c.values[0] = 0.003;
    c.values[2] = 0.15;
    c.values[3] = 0.05;
    c.timed = timed;
    c.frame = frame;
    return c;
}

}  // namespace

TEST_CASE("take recording: commands at the sample the renderer applied them, a noted scene change at its block, then the frames played") {
    DaemonOptions options;
    options.record_score = ameoto::test::temp_path("unit.take");
    options.rain_mm_per_h = 0.0;
    options.level_auto = false;
    const std::optional<FirstScene> first = read_first_scene(options, 48000.0, false);
    REQUIRE(first);
    AudioBridge bridge(std::make_unique<Renderer>(first->config), 64);
    TakeRecording take;
    REQUIRE(take.open(options));
    REQUIRE(take.begin(*first, bridge));
    std::vector<float> left(256), right(256);
    float* outputs[] = {left.data(), right.data()};
    bridge.process(256, outputs);   // frames 0..255

    REQUIRE(bridge.send(drop_command(false, 0)));      // untimed: the next block's first sample, 256
    REQUIRE(bridge.send(drop_command(true, 100)));     // late: likewise
    REQUIRE(bridge.send(drop_command(true, 1000)));    // ahead: its own sample
    Command sync;
    sync.kind = CommandKind::sync;
    REQUIRE(bridge.send(sync));                        // a reply only: not in the take
    RendererConfig material_config = first->config;
    material_config.material = *membrane_material("vinyl");
    Command swap;
    swap.kind = CommandKind::swap_surface;
    swap.object = Renderer::make_scene(material_config).release();
    take.note_swap(swap.object, swap.kind, material_config);
    REQUIRE(bridge.send(swap));
    bridge.process(256, outputs);   // 256..511
    take.drain();
    bridge.process(256, outputs);   // 512..767
    bridge.process(256, outputs);   // 768..1023: the drop at 1000 plays
    take.finish();
    RendererEvent event;   // the old umbrella, retired once the new one rang in: freed here as the daemon does
    while (bridge.poll_event(event))
        if (event.kind == RendererEventKind::retired && event.object_type == RetiredObject::umbrella_scene)
            delete static_cast<UmbrellaScene*>(event.object);

    const auto messages = read_take(*options.record_score);
    std::vector<std::string> seen;
    for (const auto& m : messages) seen.push_back(m.address + " " + std::to_string(m.address == "/take/start" ? 0 : m.args.at(0).integer));
    const std::vector<std::string> expected{"/take/start 0",   "/take/command 256", "/take/command 256", "/take/command 1000",
                                            "/take/scene 256", "/take/frames 512",  "/take/frames 1024", "/take/end 1024"};
    CHECK(seen == expected);
    protocol::TakeStart start;
    REQUIRE(protocol::read_take_start(messages.at(0), start).empty());
    CHECK(start.scene == format_scene(first->scene));
    CHECK_FALSE(start.adaptive_detail);
    protocol::TakeSceneChange change;
    REQUIRE(protocol::read_take_scene(messages.at(4), change).empty());
    CHECK(change.material.name == "vinyl");
    CHECK(bridge.take_lost() == 0);
}
