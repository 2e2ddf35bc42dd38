// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Numbers to and from the command line's text, shared by the subcommands' option parsers and reports.
//
// Interface:
//   parse_number("2.5") -> 2.5        // finite decimal, whole word; nullopt otherwise (" 1", "1x", "nan")
//   parse_unsigned("42") -> 42        // digits only, fits in 64 bits
//   fixed(3.14159, 2) -> "3.14"       // fixed-point with `digits` decimals
//   short_number(0.5) -> "0.5"        // the shortest default form (as iostream prints it)

#include <optional>
#include <string>

namespace ameoto::client {

std::optional<double> parse_number(const std::string& text);
std::optional<unsigned long long> parse_unsigned(const std::string& text);
std::string fixed(double v, int digits);
std::string short_number(double v);

}  // namespace ameoto::client
