// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/scene/output_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "engine/models/ambisonics.hpp"

namespace ameoto {

namespace {

std::optional<int> whole(const std::string& text) {
    int v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return std::nullopt;
    return v;
}

}  // namespace

std::string OutputFormat::name() const {
    switch (kind) {
        case OutputKind::stereo: return "stereo";
        case OutputKind::ears: return "ears";
        case OutputKind::ring: return "ring:" + std::to_string(channels);
        case OutputKind::ambix: return "ambix:" + std::to_string(order);
        case OutputKind::binaural: return "binaural";
    }
    return "stereo";
}

std::optional<OutputFormat> parse_output_format(const std::string& text, std::string& error) {
    const std::string known = "stereo, ears, ring:N (1..16), ambix:ORDER (1..3) or binaural";
    if (text == "stereo") return OutputFormat{OutputKind::stereo, 2, 0};
    if (text == "ears") return OutputFormat{OutputKind::ears, 2, 0};
    if (text == "binaural") return OutputFormat{OutputKind::binaural, 2, 3};
    if (text.starts_with("ring:")) {
        const auto n = whole(text.substr(5));
        if (!n || *n < 1 || *n > 16) {
            error = "'" + text + "': a ring has 1 to 16 speakers (ring:N)";
            return std::nullopt;
        }
        return OutputFormat{OutputKind::ring, *n, 0};
    }
    if (text.starts_with("ambix:")) {
        const auto n = whole(text.substr(6));
        if (!n || *n < 1 || *n > max_ambix_order) {
            error = "'" + text + "': the Ambisonic order is 1, 2 or 3 (ambix:ORDER: 4, 9 or 16 channels)";
            return std::nullopt;
        }
        return OutputFormat{OutputKind::ambix, ambix_channels(*n), *n};
    }
    error = "'" + text + "' is not an output format (" + known + ")";
    return std::nullopt;
}

OutputFormat output_format_for_channels(int channels) {
    if (channels == 2) return OutputFormat{OutputKind::stereo, 2, 0};
    return OutputFormat{OutputKind::ring, channels, 0};
}

std::vector<std::string> output_channel_names(const OutputFormat& f) {
    std::vector<std::string> names;
    switch (f.kind) {
        case OutputKind::stereo: return {"left", "right"};
        case OutputKind::ears:
        case OutputKind::binaural: return {"left ear", "right ear"};
        case OutputKind::ring:
            if (f.channels == 1) return {"mono"};
            if (f.channels == 2) return {"left", "right"};
            for (int c = 0; c < f.channels; ++c) {
                // panning.hpp's ring: the first speaker half a spacing left of front, then clockwise.
                const double spacing = 360.0 / f.channels;
                double az = spacing / 2.0 - c * spacing;
                if (az <= -180.0) az += 360.0;
                const long tenths = std::lround(az * 10.0);
                char label[48];
                std::snprintf(label, sizeof label, tenths % 10 != 0 ? "ring %d az %+.1f deg" : "ring %d az %+.0f deg", c + 1,
                              static_cast<double>(tenths) / 10.0);
                names.emplace_back(label);
            }
            return names;
        case OutputKind::ambix:
            for (int c = 0; c < f.channels; ++c) names.push_back(ambix_channel_name(c));
            return names;
    }
    return names;
}

std::string output_channel_summary(const OutputFormat& f) {
    std::string text = f.name();
    if (f.kind == OutputKind::ambix) text += " (AmbiX: ACN order, SN3D, no Condon-Shortley phase)";
    text += ": ";
    const auto names = output_channel_names(f);
    for (std::size_t i = 0; i < names.size(); ++i) text += (i ? ", " : "") + names[i];
    return text;
}

}  // namespace ameoto
