// SPDX-License-Identifier: GPL-3.0-or-later
// Settling's coarse floor is each drop's own (drop_on_canopy.hpp, "Settling"): a drop's steps, and so its
// samples, depend on its own state and the canopy only, never on another drop that has not yet touched
// the canopy. The clock, bundle and score tests compare streams in which drops arrive at different
// samples; a floor shared by the pool (read for one drop, used by all) let one drop's coarse steps change
// with another's presence.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "engine/models/drop_on_canopy.hpp"

namespace {

using ameoto::DropOnCanopy;
using ameoto::DropOnCanopyConfig;

int newest_slot(const DropOnCanopy& scene) {
    int slot = -1;
    std::uint64_t best = 0;
    for (const int d : scene.pool().active())
        if (scene.pool().serial(d) >= best) {
            best = scene.pool().serial(d);
            slot = d;
        }
    return slot;
}

struct Run {
    std::vector<float> sound;
    std::vector<ameoto::SceneMass> x_masses;   // drop X's masses at the end
    long coarse_steps = 0;
};

constexpr int x_spawn = 2400;   // 50 ms

// Drop X (3 mm, terminal speed) is spawned 6 cm over the flat canopy at x_spawn and woken at once (as a
// splash's piece flying over the 5 cm band is awake): it falls through the band's top, where the floor
// its coarse steps may use changes, lands at about 57 ms and splashes. With `other`, drop Y (3 mm) is
// spawned at sample 0 almost at rest 6 cm over another panel and woken: by x_spawn it hangs in the band,
// awake, over the membrane (where settling reads the membrane's highest point for its floor), and it
// touches nothing before about 110 ms. Stops when Y (or, alone, the same sample) comes within 1 cm of
// the membrane, well before it touches.
Run run(bool other, int frames) {
    DropOnCanopyConfig c;
    c.max_diameter = 3.2e-3;
    c.settle = true;
    c.gap_m = 0.06;
    DropOnCanopy scene(c);
    int y_slot = -1;
    if (other) {
        REQUIRE(scene.drop(3e-3, 1e-3, -0.2, 0.1));
        y_slot = newest_slot(scene);
        (void)scene.pool().body(y_slot);   // wakes it: the physics is unchanged (drop_pool.hpp, "Dormant fall")
    }
    Run r;
    float frame[1];
    int x_slot = -1;
    for (int k = 0; k < frames; ++k) {
        if (k == x_spawn) {
            REQUIRE(scene.drop(3e-3, 0.0, 0.25, 0.0));
            x_slot = newest_slot(scene);
            (void)scene.pool().body(x_slot);
        }
        scene.process_frame(frame);
        r.sound.push_back(frame[0]);
    }
    if (other) CHECK(scene.pool().lowest_z(y_slot) > 0.01);   // Y has touched nothing
    const std::uint64_t x_serial = scene.pool().serial(x_slot);
    for (const auto& m : scene.snapshot())
        if (m.serial == x_serial) r.x_masses.push_back(m);
    r.coarse_steps = scene.pool().stats().coarse_steps;
    return r;
}

}  // namespace

TEST_CASE("drop_settle: a drop's samples do not depend on another drop in the pool (per-drop coarse floor)") {
    // 100 ms: Y is still over 1 cm above the membrane (checked); X has landed and splashed for 43 ms.
    const int frames = 4800;
    const Run alone = run(false, frames);
    const Run among = run(true, frames);
    REQUIRE(alone.coarse_steps > 0);   // X steps coarsely, so its floor matters
    bool sounds = false;
    for (const float s : alone.sound) sounds = sounds || s != 0.0f;
    REQUIRE(sounds);   // X has landed
    // Exact: X's own history and the same canopy give the same arithmetic.
    long first_difference = -1;
    for (std::size_t k = 0; k < alone.sound.size() && first_difference < 0; ++k)
        if (alone.sound[k] != among.sound[k]) first_difference = static_cast<long>(k);
    CHECK(first_difference == -1);
    REQUIRE(alone.x_masses.size() == among.x_masses.size());
    int moved = 0;
    for (std::size_t m = 0; m < alone.x_masses.size(); ++m) {
        const auto &a = alone.x_masses[m].position, &b = among.x_masses[m].position;
        if (a.x != b.x || a.y != b.y || a.z != b.z) ++moved;
    }
    CHECK(moved == 0);
}
