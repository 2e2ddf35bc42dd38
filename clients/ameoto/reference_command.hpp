// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// `ameoto reference [VALIDATION...] [--dx M] [--json]`: the offline air reference's validations (issue 19,
// engine/reference/validations.hpp) at a chosen grid spacing, each figure printed against its target;
// needs no server. docs/cli-offline.md, "ameoto reference"; docs/air-reference.md has the method and the figures.
//
// Interface:
//   int status = run_reference(words, io);   // words: everything after "ameoto reference"
//   std::cout << reference_usage();          // ameoto reference --help, ameoto help reference
//   ReferenceOptions o; std::string error;
//   ReferenceParse p = parse_reference_options(words, o, error);
//
// Validations: piston, disc, timpani, reflection, canopy, canopy-bands, canopy-drop (default: the first four). Output: one line per
// figure (target, result, ok or MISS), or with --json one JSON object. Exit: 0 every figure within its
// target; 1 any missed; 2 usage error.

#include <string>
#include <vector>

#include "clients/ameoto/command_io.hpp"

namespace ameoto::client {

struct ReferenceOptions {
    std::vector<std::string> validations;   // empty: piston, disc, timpani, reflection
    double dx_m = 0.0;                      // 0: each validation's own full-resolution spacing
    bool json = false;
};

enum class ReferenceParse { run, help, error };

ReferenceParse parse_reference_options(const CommandWords& words, ReferenceOptions& options, std::string& error);
int run_reference(const CommandWords& words, const CommandIo& io);
std::string reference_usage();

}  // namespace ameoto::client
