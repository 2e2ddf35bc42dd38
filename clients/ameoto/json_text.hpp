// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The few JSON spellings the CLI prints (status --json, bench --json), in one place.
//
// Interface:
//   json_string("a\"b")   -> "\"a\\\"b\""   // quotes, escapes " \ and control characters
//   json_number(3.25)     -> "3.25"         // 6 significant digits; NaN and Inf -> null (JSON has neither)

#include <string>

namespace ameoto::client {

std::string json_string(const std::string& text);
std::string json_number(double value);

}  // namespace ameoto::client
