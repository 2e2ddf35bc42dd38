// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The output format a stream is started with (--format, a scene file's `output format=`): what its
// channels carry. Chosen once, at start: a stream keeps its channels (JACK ports, a WAV's layout).
//
// Interface:
//   std::optional<OutputFormat> f = parse_output_format("ambix:3", error);   // none: error says why
//   f->name()                       // "ambix:3", the text it was parsed from (canonical)
//   f->channels                     // 2, 2, N, 4/9/16, 2
//   output_channel_names(*f)        // one label a channel: "left", "ACN 0 W", "ring 1 az +45 deg", ...
//   output_format_for_channels(n)   // what --channels N meant before --format: stereo for 2, ring:N else
//
// Formats (docs/output-formats.md):
//   stereo     two channels, each sound panned by its azimuth (constant power, panning.hpp)
//   ears       two listening points 0.18 m apart (the umbrella; other surfaces are panned as stereo)
//   ring:N     N = 1..16 speakers on a ring (1: mono), panned pairwise (panning.hpp)
//   ambix:N    Ambisonics of order N = 1..3, AmbiX (ACN order, SN3D, no Condon-Shortley phase):
//              (N + 1)^2 channels (models/ambisonics.hpp)
//   binaural   headphones: the renderer makes the third-order bus (apply_output_format: 16 channels) and
//              the caller decodes it to two ears through measured HRIRs (a SOFA file, --hrtf;
//              engine/render/binaural_decoder.hpp): ameotod's audio bridge, the renders' render_output

#include <optional>
#include <string>
#include <vector>

namespace ameoto {

enum class OutputKind { stereo, ears, ring, ambix, binaural };

struct OutputFormat {
    OutputKind kind = OutputKind::stereo;
    int channels = 2;
    int order = 0;   // ambix: 1..3; binaural: the order it decodes (3)
    std::string name() const;
    bool operator==(const OutputFormat&) const = default;
};

std::optional<OutputFormat> parse_output_format(const std::string& text, std::string& error);
OutputFormat output_format_for_channels(int channels);
std::vector<std::string> output_channel_names(const OutputFormat& format);
// One line for a WAV's comment and the log: "ambix:1 (AmbiX ACN/SN3D): ACN 0 W, ACN 1 Y, ACN 2 Z, ACN 3 X".
std::string output_channel_summary(const OutputFormat& format);

}  // namespace ameoto
