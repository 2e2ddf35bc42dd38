// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ameotod's output format, settled before the backend opens (its channel count is the ports' and the
// WAV's): --format, else the starting scene file's `output format=`, else what --channels means.
//
// Interface (control thread, at start):
//   if (!resolve_output_format(options)) return 1;   // options.format and options.channels set; false:
//                                                    // a format this ameotod cannot play (logged):
//                                                    // binaural with an --hrtf file it cannot read
//   std::vector<std::string> labels = output_channel_names(*options.format);   // JACK pretty names
// A scene that cannot be read is left to read_first_scene, which names its file and line.

#include "server/options.hpp"

namespace ameoto {

bool resolve_output_format(DaemonOptions& options);

}  // namespace ameoto
