// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/format_option.hpp"

#include <stdexcept>

namespace ameoto::client {

namespace {
const char* const both = "give --format or --channels, not both (ring:N is N channels)";
}

bool FormatChoice::take_format(const std::string& value, std::string& error) {
    if (channels) {
        error = both;
        return false;
    }
    std::string why;
    format = parse_output_format(value, why);
    if (!format) error = "--format: " + why;
    return format.has_value();
}

bool FormatChoice::take_channels(int n, std::string& error) {
    if (format) {
        error = both;
        return false;
    }
    channels = n;
    return true;
}

bool take_hrtf_option(const std::string& value, std::string& hrtf, std::string& error) {
    if (value.empty()) {
        error = "--hrtf needs a SOFA file";
        return false;
    }
    hrtf = value;
    return true;
}

OutputFormat FormatChoice::resolve(const std::string& scene_format, int default_channels) const {
    if (format) return *format;
    if (channels) return output_format_for_channels(*channels);
    if (!scene_format.empty()) {
        std::string why;
        const auto f = parse_output_format(scene_format, why);
        if (!f) throw std::invalid_argument("output format " + why);
        return *f;
    }
    return output_format_for_channels(default_channels);
}

std::string format_option_usage() {
    return "  --format F          stereo (default), ears, ring:N (1..16 speakers), ambix:ORDER\n"
           "                      (Ambisonics, ORDER 1..3: 4, 9 or 16 channels, ACN/SN3D), binaural\n"
           "                      (render scene: the third-order bus decoded to two ears through\n"
           "                      measured HRIRs, --hrtf); docs/output-formats.md. Default: the\n"
           "                      scene's 'output format=', else what --channels says\n";
}

}  // namespace ameoto::client
