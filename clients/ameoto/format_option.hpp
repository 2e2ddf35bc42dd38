// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The renders' --format option (engine/scene/output_format.hpp), shared by render scene, score and drop.
//
// Interface:
//   FormatChoice f;                                   // in a command's options
//   if (!f.take_format(value, error)) ...             // --format F; error: why (and --channels given too)
//   if (!f.take_channels(n, error)) ...               // --channels N
//   OutputFormat out = f.resolve(scene.output_format);   // --format, else the scene's key, else --channels'
//   if (!take_hrtf_option(value, o.hrtf, error)) ...     // --hrtf FILE.sofa (binaural; checked when opened)
//   std::string usage = format_option_usage();           // the --format lines of --help

#include <optional>
#include <string>

#include "engine/scene/output_format.hpp"

namespace ameoto::client {

struct FormatChoice {
    std::optional<OutputFormat> format;
    std::optional<int> channels;
    bool take_format(const std::string& value, std::string& error);
    bool take_channels(int n, std::string& error);
    // scene_format: the scene file's `output format=` (empty: none); throws std::invalid_argument if it
    // does not parse (validate_scene has checked it).
    OutputFormat resolve(const std::string& scene_format = "", int default_channels = 2) const;
};

// --hrtf FILE.sofa: the path, not empty (the file itself is read, and refused with its reason, when the
// binaural decoder is built: RenderOutput::make).
bool take_hrtf_option(const std::string& value, std::string& hrtf, std::string& error);

std::string format_option_usage();

}  // namespace ameoto::client
