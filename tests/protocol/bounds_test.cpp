// SPDX-License-Identifier: GPL-3.0-or-later
// Every size the receive path accepts is bounded, and the bounds agree with what the engine can hold
// (docs/reliability.md, "Bounds").

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "engine/render/renderer.hpp"
#include "engine/scene/scene_description.hpp"
#include "protocol/receive.hpp"

using namespace ameoto;
using namespace ameoto::protocol;

TEST_CASE("every numeric argument in the table has a finite range, and /lod's limit is the drop pool's capacity") {
    for (const AddressSpec& spec : address_table())
        for (const ArgumentSpec& a : spec.arguments) {
            INFO(spec.address << " " << a.name);
            if (a.kind == ArgumentKind::text) continue;
            CHECK(std::isfinite(a.min));
            CHECK(std::isfinite(a.max));
            CHECK(a.min < a.max);
        }
    const AddressSpec* lod = find_address("/lod");
    REQUIRE(lod);
    CHECK(lod->arguments[1].max == Renderer::max_full_drops);
    // /surface/add's sizes and positions are the scene file's (a surface added over OSC can be saved).
    const AddressSpec* add = find_address("/surface/add");
    REQUIRE(add);
    SceneDescription scene;
    SurfaceDescription f{"edge", SurfaceKind::plate, "tin", add->arguments[3].max, add->arguments[4].max,
                         add->arguments[5].max, add->arguments[6].min, add->arguments[7].max};
    scene.surfaces.push_back(f);
    CHECK(validate_scene(scene) == "");
    scene.surfaces[0].size_x_m = std::nextafter(add->arguments[3].max, 1e9);
    CHECK(validate_scene(scene) != "");
}

TEST_CASE("the largest UDP datagram is handled: a 64 KiB string is refused, 4093 messages in one bundle each validated") {
    ProtocolContext context;
    // The daemon's receive buffer is 65536 bytes (server/osc/udp_endpoint.hpp), above IPv4's largest
    // UDP payload (65507): no datagram is cut. A string that fills it is refused by the 255 bound.
    const auto big = encode_message("/scene/load", {OscArgument::from_string(std::string(65400, 'a'))});
    REQUIRE(big.size() <= 65507);
    const ReceivedPacket p = receive_packet(big.data(), big.size(), context);
    REQUIRE(p.messages.size() == 1);
    CHECK(p.messages[0].validation.reason == "argument 1 name: longer than 255 characters");
    // The most messages a datagram can carry: 8-byte "/status" messages (12 with the size) in a bundle.
    const auto status = encode_message("/status", {});
    std::vector<std::vector<unsigned char>> many((65507 - 16) / (status.size() + 4), status);
    const auto bundle = encode_bundle(Timetag{}, many);
    REQUIRE(bundle.size() <= 65507);
    const ReceivedPacket q = receive_packet(bundle.data(), bundle.size(), context);
    REQUIRE_FALSE(q.failed());
    CHECK(q.messages.size() == many.size());
    MESSAGE(q.messages.size() << " messages in one datagram");
}

TEST_CASE("scene bounds: at most 16 surfaces, names of at most 32 characters") {
    SceneDescription scene;
    for (int i = 0; i < max_scene_surfaces; ++i) {
        // Appended rather than "s" + std::to_string(i): g++ 12 warns falsely on that (-Wrestrict, GCC PR 105329).
        std::string name = "s";
        name += std::to_string(i);
        scene.surfaces.push_back({name, SurfaceKind::water, "pond", 1, 1, 0, 0, 0});
    }
    CHECK(validate_scene(scene) == "");
    scene.surfaces.push_back({"one-more", SurfaceKind::water, "pond", 1, 1, 0, 0, 0});
    CHECK(validate_scene(scene) == "more than 16 surfaces");
    CHECK(is_scene_name(std::string(32, 'a')));
    CHECK_FALSE(is_scene_name(std::string(33, 'a')));
}
