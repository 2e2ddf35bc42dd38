// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// /status.reply, field by field: names, units and the two ways `ameoto status` prints it.
//
// Interface:
//   StatusReport r = parse_status_reply(message);    // r.error empty when the shape is right
//   out << format_status_text(r);                      // "cpu average: 3.1 %" ..., one per line
//   out << format_status_json(r);                      // {"cpu_average_percent":3.1,...} + '\n'
//   for (const StatusField& f : status_fields()) ...   // the table, for docs and tests
//
// The fields, in the order the server sends them (server/daemon.cpp, reply_status; type tags
// "fffiiiiififfsfif"), are the ones in status_fields(). Numbers are accepted with any numeric tag
// (a server that sends 48000 as 'i' still reads), but a reply with too few arguments, or text
// where a number belongs, is refused: the fields would be misnamed otherwise. Arguments beyond
// the table (a newer server) are ignored.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"

namespace ameoto::client {

enum class StatusKind { real, integer, text };

struct StatusField {
    const char* label;      // text output: "cpu average"
    const char* json_key;   // --json: snake_case with the unit in the name where it has one
    const char* unit;       // text output, after the value; "" for counts and names
    StatusKind kind;
    int decimals;           // text output: at most this many (trailing zeros dropped)
};

std::span<const StatusField> status_fields();

struct StatusValue {
    double number = 0.0;
    std::int64_t integer = 0;
    std::string text;
};

struct StatusReport {
    std::vector<StatusValue> values;   // one per status_fields() entry
    std::string error;
};

StatusReport parse_status_reply(const protocol::DecodedMessage& message);
std::string format_status_text(const StatusReport& report);
std::string format_status_json(const StatusReport& report);

}  // namespace ameoto::client
