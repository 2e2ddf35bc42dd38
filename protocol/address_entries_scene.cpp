// SPDX-License-Identifier: GPL-3.0-or-later
// The scene's rows of the OSC address table (address_entries.hpp): loading and saving it, its surfaces,
// and the edits that rebuild it (/accuracy, /canopy/air).
#include "protocol/address_entries.hpp"

#include <optional>

namespace ameoto::protocol::entries {

void add_scene_entries(std::vector<AddressSpec>& t) {
    auto scene_load = [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
        if (!is_scene_name(a.texts[0]))
            return "scene name '" + a.texts[0] + "' is not 1-32 of A-Z a-z 0-9 - _ (a name, not a path)";
        r.action = Action::load_scene;
        r.scene_name = a.texts[0];
        return std::nullopt;
    };
    t.push_back({"/scene",
                 {{"name", ArgumentKind::text, "", 0, 0, false,
                   "a built-in scene (umbrella, pond, tin-roof, forest, street) or one saved in the scene folder", "pond"}},
                 "Load a scene (the same as /scene/load, under the short name of the core contract).",
                 "/done /scene (once it plays)",
                 scene_load});
    t.back().query = {true, {}, "/scene.reply s name: the scene playing (its name as loaded or saved)"};
    t.push_back({"/scene/load",
                 {{"name", ArgumentKind::text, "", 0, 0, false,
                   "a built-in scene (umbrella, pond, tin-roof, forest, street) or one saved in the scene folder", "pond"}},
                 "Load a scene: its surfaces, rain, listener and level of detail; the old scene rings out.",
                 "/done /scene/load (once it plays)",
                 scene_load});
    t.back().query = {true, {}, "/scene/load.reply s name: the scene playing"};
    t.push_back({"/scene/save",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "the name to save the current scene under", "my-rain"}},
                 "Save the current scene (as it plays now) into the scene folder as NAME.scene, atomically.",
                 "/done /scene/save (once written)",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     if (!is_scene_name(a.texts[0]))
                         return "scene name '" + a.texts[0] + "' is not 1-32 of A-Z a-z 0-9 - _ (a name, not a path)";
                     if (builtin_scene(a.texts[0]))
                         return "'" + a.texts[0] + "' is a built-in scene; save under another name";
                     r.action = Action::save_scene;
                     r.scene_name = a.texts[0];
                     return std::nullopt;
                 }});
}

void add_surface_entries(std::vector<AddressSpec>& t) {
    auto surface_arguments = std::vector<ArgumentSpec>{
        {"name", ArgumentKind::text, "", 0, 0, false, "the surface's name (1-32 of A-Z a-z 0-9 - _)", "roof"},
        {"kind", ArgumentKind::text, "", 0, 0, false, "water, plate or ground (the umbrella comes with scenes)", "plate"},
        {"material", ArgumentKind::text, "", 0, 0, false, "water: pond, puddle; plate: tin, glass, car-roof; ground: leaves, soil",
         "tin"},
        {"size_x", ArgumentKind::number, "m", 0.05, 100.0, false, "extent along x"},
        {"size_y", ArgumentKind::number, "m", 0.05, 100.0, false, "extent along y"},
        {"x", ArgumentKind::number, "m", -1000.0, 1000.0, false, "centre"},
        {"y", ArgumentKind::number, "m", -1000.0, 1000.0, false, "centre"},
        {"z", ArgumentKind::number, "m", -1000.0, 1000.0, false, "height (the ground is 0)"}};
    auto surface_build = [](SceneEdit::Op op) {
        return [op](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
            SurfaceDescription f;
            f.name = a.texts[0];
            if (!is_scene_name(f.name)) return "surface name '" + f.name + "' is not 1-32 of A-Z a-z 0-9 - _";
            const auto kind = surface_kind(a.texts[1]);
            if (!kind || *kind == SurfaceKind::umbrella) return "kind '" + a.texts[1] + "' is not water, plate or ground";
            f.kind = *kind;
            f.material = a.texts[2];
            f.size_x_m = a.numbers[0];
            f.size_y_m = a.numbers[1];
            f.x_m = a.numbers[2];
            f.y_m = a.numbers[3];
            f.z_m = a.numbers[4];
            r.action = Action::edit_scene;
            r.edit.op = op;
            r.edit.surface = f;
            return std::nullopt;
        };
    };
    t.push_back({"/surface/add", surface_arguments, "Add a surface to the scene (rebuilt off the audio thread).",
                 "/done /surface/add (once it sounds)", surface_build(SceneEdit::Op::surface_add)});
    t.push_back({"/surface/set", surface_arguments, "Change a surface of the scene: kind, material, size, position.",
                 "/done /surface/set (once it sounds)", surface_build(SceneEdit::Op::surface_set)});
    t.back().query = {true,
                      {{"name", ArgumentKind::text, "", 0, 0, false, "a surface of the scene", "umbrella"}},
                      "/surface/set.reply s name, s kind, s material, f size_x, f size_y, f x, f y, f z (m)"};
    t.push_back({"/surfaces", {}, "List the surfaces of the scene playing.",
                 "/surfaces.reply s name ... (one string per surface, in the scene's order; none for an empty scene)",
                 [](const ValidatedArguments&, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::query;
                     r.query_address = "/surfaces";
                     return std::nullopt;
                 }});
    t.push_back({"/surface/remove",
                 {{"name", ArgumentKind::text, "", 0, 0, false, "the surface's name", "roof"}},
                 "Remove a surface from the scene.",
                 "/done /surface/remove",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     if (!is_scene_name(a.texts[0])) return "surface name '" + a.texts[0] + "' is not 1-32 of A-Z a-z 0-9 - _";
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::surface_remove;
                     r.edit.surface.name = a.texts[0];
                     return std::nullopt;
                 }});
}

void add_accuracy_entry(std::vector<AddressSpec>& t) {
    // Appended (issue 6): the accuracy knob (engine/core/method_choice.hpp, docs/accuracy.md).
    t.push_back({"/accuracy",
                 {{"measure", ArgumentKind::text, "", 0, 0, false,
                   "cents (frequency error), db (log-spectral distance) or off (the default method)",
                   "off"},
                  {"budget", ArgumentKind::number, "cents or dB", AccuracyLimits::cents_min, AccuracyLimits::cents_max, true,
                   "the largest error allowed: cents 0.001..1200, db 0.001..60", "5"}},
                 "Set the scene's accuracy budget: the canopy runs the cheapest measured method within it (the scene is "
                 "rebuilt off the audio thread). With no arguments, ask for the budget and the method chosen.",
                 "/done /accuracy (once the rebuilt scene plays); with no arguments: /accuracy.reply",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     // Nothing is written into the request until the whole message is accepted.
                     std::optional<AccuracyBudget> accuracy;
                     if (a.texts[0] == "off") {
                         if (!a.numbers.empty()) return "'off' takes no budget";
                     } else {
                         AccuracyMeasure measure{};
                         if (!parse_accuracy_measure(a.texts[0], measure))
                             return "measure '" + a.texts[0].substr(0, 64) + "' is not one of cents, db, off";
                         if (a.numbers.empty()) return "give the budget: /accuracy " + a.texts[0] + " VALUE";
                         const AccuracyBudget budget{measure, a.numbers[0]};
                         if (std::string why = validate_accuracy_budget(budget); !why.empty()) return why;
                         accuracy = budget;
                     }
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::accuracy;
                     r.edit.accuracy = accuracy;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/accuracy.reply s measure, f budget, s method, i sub_steps, i modes, s why"};
}

void add_canopy_air_entry(std::vector<AddressSpec>& t) {
    // Appended (issue 19): the canopy in air or in vacuum (engine/models/air_canopy.hpp, docs/canopy-air.md).
    t.push_back({"/canopy/air",
                 {{"on", ArgumentKind::integer, "", 0.0, 1.0, false,
                   "1: the umbrella's canopy in air (its air-loaded modes heard as dipoles); 0: in vacuum, baffled (the seed's)",
                   "1"}},
                 "Put the scene's umbrella canopy in air (1) or in vacuum (0). The scene is rebuilt off the audio thread "
                 "and swapped in, as /material/surface does; saved scenes keep it (the umbrella's air= key). With no "
                 "arguments, ask which.",
                 "/done /canopy/air (once the rebuilt scene plays); /fail /canopy/air when the scene has no umbrella",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::air;
                     r.edit.air = a.numbers[0] != 0.0;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/canopy/air.reply i 1|0: whether the umbrella's canopy is in air (0 with no umbrella)"};
}

void add_canopy_impact_entry(std::vector<AddressSpec>& t) {
    // Appended (issue 19, part 3): how drops meet the canopy (engine/models/wet_impact.hpp, docs/impacts.md).
    t.push_back({"/canopy/impact",
                 {{"model", ArgumentKind::text, "", 0, 0, false,
                   "wet: as a liquid (impulse m V, spreading; Gordillo et al. 2018); seed: the seed's elastic exchange", "wet"}},
                 "Choose how drops meet the scene's umbrella canopy: wet (the default, a real drop's impulse) or seed (the "
                 "seed paper's elastic exchange, twice that impulse). The scene is rebuilt off the audio thread, its "
                 "impact templates and texture grains recorded again from the new model, and swapped in, as /canopy/air "
                 "is; saved scenes keep it (the umbrella's impact= key). With no arguments, ask which.",
                 "/done /canopy/impact (once the rebuilt scene plays); /fail /canopy/impact for another model name or "
                 "when the scene has no umbrella",
                 [](const ValidatedArguments& a, const ProtocolContext&, Request& r) -> std::optional<std::string> {
                     const std::optional<ImpactModel> model = find_impact_model(a.texts[0]);
                     if (!model) return "'" + a.texts[0] + "' is not wet or seed";
                     r.action = Action::edit_scene;
                     r.edit.op = SceneEdit::Op::impact;
                     r.edit.impact = *model;
                     return std::nullopt;
                 }});
    t.back().query = {true, {}, "/canopy/impact.reply s wet|seed: how drops meet the umbrella's canopy (wet with no umbrella)"};
}

}  // namespace ameoto::protocol::entries
