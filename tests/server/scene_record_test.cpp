// SPDX-License-Identifier: GPL-3.0-or-later
// The control thread's record of the scene as the engine has applied it (server/scene_record.hpp):
// what the queries answer and /scene/save writes.
#include "server/scene_record.hpp"

#include <doctest/doctest.h>

#include "engine/models/liquid.hpp"
#include "engine/models/membrane.hpp"

namespace {

ameoto::SceneRecord street_record() {
    return ameoto::SceneRecord(*ameoto::builtin_scene("street"), *ameoto::find_liquid("water"), *ameoto::membrane_material("nylon"));
}

ameoto::Command rain_at(double mm_per_h, std::uint64_t frame) {
    ameoto::Command c;
    c.kind = ameoto::CommandKind::rain_rate;
    c.values[0] = mm_per_h;
    c.timed = frame > 0;
    c.frame = frame;
    return c;
}

}  // namespace

TEST_CASE("scene record: timed changes take effect in the order of their frames once played; ties as sent") {
    ameoto::SceneRecord record = street_record();
    const double start = record.scene().rain.rate_mm_per_h;
    record.apply_at_frame(rain_at(30, 2000));
    record.apply_at_frame(rain_at(20, 1000));
    record.apply_at_frame(rain_at(25, 2000));   // same frame as the 30: sent after it, so it wins
    record.apply_due(999);
    CHECK(record.scene().rain.rate_mm_per_h == start);
    record.apply_due(1000);
    CHECK(record.scene().rain.rate_mm_per_h == 20);
    record.apply(rain_at(5, 0));   // an untimed change: in effect at once
    CHECK(record.scene().rain.rate_mm_per_h == 5);
    record.apply_due(5000);
    CHECK(record.scene().rain.rate_mm_per_h == 25);
    record.apply_due(6000);        // nothing left waiting
    CHECK(record.scene().rain.rate_mm_per_h == 25);
}

TEST_CASE("scene record: at most 4096 timed changes wait; more are played but not recorded") {
    ameoto::SceneRecord record = street_record();
    for (std::size_t n = 0; n < ameoto::SceneRecord::max_timed_settings; ++n) record.apply_at_frame(rain_at(1, 100));
    record.apply_at_frame(rain_at(99, 200));   // one too many: dropped from the record
    record.apply_due(1000);
    CHECK(record.scene().rain.rate_mm_per_h == 1);
}

TEST_CASE("scene record: refusals name what would break; a material renames the umbrella's; a load keeps waiting changes") {
    ameoto::SceneRecord record = street_record();
    CHECK(record.refusal(rain_at(12, 0)).empty());
    ameoto::Command far;
    far.kind = ameoto::CommandKind::listener;
    far.values[0] = 5000.0;   // carries the umbrella out of range
    CHECK_FALSE(record.refusal(far).empty());
    CHECK(record.scene() == *ameoto::builtin_scene("street"));   // a refusal is only a question

    record.material_changed(*ameoto::membrane_material("vinyl"));
    CHECK(record.material().name == "vinyl");
    for (const ameoto::SurfaceDescription& s : record.scene().surfaces)
        if (s.kind == ameoto::SurfaceKind::umbrella) CHECK(s.material == "vinyl");
    record.liquid_changed(*ameoto::find_liquid("milk"));
    CHECK(record.liquid().name == "milk");

    record.apply_at_frame(rain_at(42, 500));
    record.loaded(*ameoto::builtin_scene("pond"), *ameoto::membrane_material("nylon"));
    CHECK(record.scene().name == "pond");
    record.apply_due(500);   // the renderer keeps its scheduled commands across a load, and so does the record
    CHECK(record.scene().rain.rate_mm_per_h == 42);
}

TEST_CASE("scene record: the head's orientation is kept for its query, timed like the rest, outside the scene") {
    ameoto::SceneRecord record = street_record();
    const ameoto::SceneDescription before = record.scene();
    ameoto::Command c;
    c.kind = ameoto::CommandKind::orientation;
    c.values[0] = 0.5;
    c.values[1] = -0.2;
    c.values[2] = 0.1;
    CHECK(record.refusal(c).empty());
    c.timed = true;
    c.frame = 1000;
    record.apply_at_frame(c);
    record.apply_due(999);
    CHECK(record.orientation()[0] == 0.0);
    record.apply_due(1000);
    CHECK(record.orientation() == std::array<double, 3>{0.5, -0.2, 0.1});
    CHECK(ameoto::format_scene(record.scene()) == ameoto::format_scene(before));   // never in the saved scene
    record.loaded(before, record.material());   // a new scene: the head stays as it is turned
    CHECK(record.orientation()[1] == -0.2);
}
