// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/output_choice.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "engine/render/renderer.hpp"
#include "server/log_lines.hpp"
#include "server/scene_store.hpp"

namespace ameoto {

bool resolve_output_format(DaemonOptions& options) {
    if (!options.format && !options.channels_given) {
        try {
            const SceneDescription scene = is_scene_name(options.scene)
                                               ? SceneStore(options.scene_folder ? std::filesystem::path(*options.scene_folder)
                                                                                 : SceneStore::default_folder())
                                                     .load(options.scene)
                                               : SceneStore::read_file(options.scene);
            std::string error;
            if (!scene.output_format.empty()) options.format = parse_output_format(scene.output_format, error);
        } catch (const std::exception&) {
            // read_first_scene reports it, with the file, line and key.
        }
    }
    if (!options.format) options.format = output_format_for_channels(options.channels);
    // Binaural: a SOFA file that is not there is said before the ports open; what is wrong inside one is
    // said when the decoder is built (BinauralDecoder::create), before audio starts.
    if (options.format->kind == OutputKind::binaural && ::access(options.hrtf.c_str(), R_OK) != 0) {
        warn("--format binaural: cannot read the HRTF set " + options.hrtf + " (" + std::strerror(errno) +
             "; --hrtf FILE.sofa, or install libmysofa1 for the default)");
        return false;
    }
    options.channels = options.format->channels;
    return true;
}

}  // namespace ameoto
