// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto render score FILE -o OUT.wav`: a score of timed OSC messages (score_file.hpp: scsynth's
// binary format or a text score) rendered offline with the engine ameotod runs, every message at its
// sample (round(time x rate)), as fast as the CPU allows.
//
// Interface (the command line's thread):
//   RenderScoreOptions o;
//   RenderParse p = parse_render_score_options(words, o, error);   // words after "ameoto render score"
//   int status = run_render_score(o, io);   // 0 rendered; 1 refused (file, message, scene); 2 usage
//
// Every message is validated as ameotod validates one arriving over UDP (protocol::validate, with the
// scene's surfaces; a rain, wind or listener change that would leave the scene invalid is refused as
// the daemon refuses it), all of them before anything is rendered: one invalid message refuses the
// score with its time, where it is (FILE:LINE, or bundle and message) and the reason, and no WAV is
// written. Server-only messages (/status, /version, /notify, /reply/port, /sync, /quit, queries) have
// nothing to do offline and are ignored (counted in the summary). Messages that make the server build
// a new scene (/scene/load, /scene/save, /material/*, /rain/dsd, /surface/*, /accuracy) are refused in
// this version: give the render the scene (--scene FILE.scene) instead. Of scsynth's own messages that
// SuperCollider's Score writes, /g_new (the default group, added at time 0) is ignored and /c_set (the
// conventional end marker) sets the render's length when --seconds is not given.
// A take recorded by `ameotod --record-score` (its first message /take/start) is rendered by
// render_take.hpp: the live stream again, from the state it names.
// Reproducible to the sample: the same score, scene, seed and rate give the same samples whatever the
// block size (--block), since the renderer applies each command at its sample within a block.

#include <cstdint>
#include <optional>
#include <string>

#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/format_option.hpp"
#include "clients/ameoto/render_drop.hpp"

namespace ameoto::client {

struct RenderScoreOptions {
    std::string score_path;                // the score (required)
    std::string wav_path;                  // -o (required)
    std::string scene = "umbrella";        // a built-in name, or a path ending in .scene
    std::optional<double> rain_mm_per_h;   // 0..500; default: the scene's
    std::optional<double> seconds;         // 0.01..86400; default: the end marker, or the last message + 3 s
    int rate = 48000;                      // Hz
    std::uint64_t seed = 1;
    FormatChoice format;                   // --format or --channels; default: the scene's, else stereo
    int block = 512;                       // frames per renderer call, 1..8192 (changes nothing in the samples)
    std::string hrtf = "/usr/share/libmysofa/default.sofa";   // --hrtf FILE.sofa: binaural's HRIRs
    bool quiet = false;
    std::string setup_option;              // the first of --scene, --rain, --rate, --seed, --channels given
                                           // (a recorded take names its own: render_take.hpp)
};

RenderParse parse_render_score_options(const CommandWords& words, RenderScoreOptions& options, std::string& error);
int run_render_score(const RenderScoreOptions& options, const CommandIo& io);
std::string render_score_usage();

}  // namespace ameoto::client
