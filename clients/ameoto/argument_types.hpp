// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Command-line words -> OSC arguments, for `ameoto send`.
//
// Interface:
//   OscArgument a = infer_argument("30");            // 'i' 30
//   TypedArguments t = typed_arguments("fffs", {"3", "0", "0.2", "umbrella"});
//   if (!t.error.empty()) usage error (exit 2), t.error says which argument and why
//   else send t.arguments
//
// Inference, per word: an integer literal ("30", "-2", "+7") -> 'i' ('h' when it does not fit 32
// bits); a number with '.' or an exponent ("0.2", "1e3", ".5") -> 'f' ('d' when it does not fit a
// float, so the server sees the real value and says it is out of range instead of getting inf);
// "true"/"false" -> 'T'/'F'; anything else -> 's'. Integers may go out as 'i' because the server
// coerces i, h, f and d alike for number arguments (protocol/address_table.hpp).
//
// Explicit types (--types) replace inference for every argument: one letter per word, a leading
// ',' allowed as in OSC type tags. Letters: i h (integers), f d (floats), s (string),
// T (the word must be "true"), F (the word must be "false"). A word that does not parse as its
// letter's type is an error; nothing is guessed. No 'S' (symbol): protocol::encode_message has no
// case for it and would send nil instead.

#include <string>
#include <string_view>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::client {

protocol::OscArgument infer_argument(std::string_view word);

struct TypedArguments {
    std::vector<protocol::OscArgument> arguments;
    std::string error;   // empty on success
};

TypedArguments inferred_arguments(const std::vector<std::string>& words);
TypedArguments typed_arguments(std::string_view types, const std::vector<std::string>& words);

}  // namespace ameoto::client
