// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto render score TAKE -o OUT.wav` where TAKE is what `ameotod --record-score` wrote (its first
// message /take/start: protocol/take_messages.hpp): the live stream rendered again offline.
//
// The render starts from the state the take names (the scene's full description, seed, rate, output format,
// node, level gain, limiter) and applies every recorded command at the sample the engine applied it, and
// every scene change at the sample it was swapped in, built from its full description as ameotod built
// it (a load on the stream's base with its level gain, material and liquid; a material or liquid change
// on the first scene's umbrella), synchronously before that sample. Offline nothing is shed: when the
// live stream ran with --fixed-detail the WAV is the live one sample for sample; otherwise it is the
// same performance at the full detail the live stream may have shed. The length is the take's own (its
// last /take/frames or /take/end) unless --seconds says otherwise.
//
// Interface (the command line's thread):
//   if (is_take(score)) return run_render_take(options, score, io);   // 0 rendered; 1 refused

#include "clients/ameoto/command_io.hpp"
#include "clients/ameoto/render_score.hpp"
#include "clients/ameoto/score_file.hpp"

namespace ameoto::client {

bool is_take(const ScoreFile& score);
int run_render_take(const RenderScoreOptions& options, const ScoreFile& score, const CommandIo& io);

}  // namespace ameoto::client
