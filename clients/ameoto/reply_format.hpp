// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Server replies as one readable line each, the way oscdump prints them (without its type tags):
//   /fail "/rain/rate" "argument 1 rate (mm/h): 900 is outside 0..500"
//   /synced 7
//   /status.reply 3.1 5.2 120.0 3 0 0 0 0 48000.0 256 96000 2.0 "null"
//
// Interface:
//   std::string line = format_message(decoded_message);
//   std::string word = format_argument(decoded_message.args[0]);
//
// Why floats always show a '.': a reply that carries 48000 as 'i' where the protocol says 'f'
// is a bug worth seeing, so 'f'/'d' print as "48000.0" and 'i'/'h' as "48000". Strings are quoted
// with C escapes so spaces, quotes and control characters stay visible.

#include <string>

#include "protocol/osc_codec.hpp"

namespace ameoto::client {

std::string format_argument(const protocol::OscArgument& argument);
std::string format_message(const protocol::DecodedMessage& message);

// Shortest text that reads back as the same float (3.1f -> "3.1", not "3.0999999").
std::string shortest_float(float value);
std::string shortest_double(double value);

}  // namespace ameoto::client
