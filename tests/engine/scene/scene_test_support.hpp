// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Helpers the rain-scene tests share: terminal speed by diameter in mm, a named drop size distribution,
// and the message a scene file's parse refuses with.
//
// Interface:
//   double v = v_of_mm(2.0);                          // m/s, Gunn-Kinzer (engine/scene/terminal_speed.hpp)
//   NamedDsd{"Marshall-Palmer", DropSizeDistribution::marshall_palmer()}
//   std::string e = error_of(scene_text);             // parse_scene's SceneFileError text, "" when it parses

#include <string>

#include "engine/scene/drop_size_distribution.hpp"
#include "engine/scene/scene_description.hpp"
#include "engine/scene/terminal_speed.hpp"

namespace ameoto::test {

inline double v_of_mm(double d_mm) { return ameoto::terminal_speed(d_mm * 1e-3); }

struct NamedDsd {
    const char* name;
    ameoto::DropSizeDistribution dsd;
};

inline std::string error_of(const std::string& text) {
    try {
        ameoto::parse_scene(text, "test.scene");
    } catch (const ameoto::SceneFileError& e) {
        return e.what();
    }
    return "";
}

}  // namespace ameoto::test
