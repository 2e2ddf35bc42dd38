// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/status_report.hpp"

#include <cmath>
#include <cstdio>

#include "clients/ameoto/json_text.hpp"
#include "clients/ameoto/reply_format.hpp"

namespace ameoto::client {
namespace {

constexpr StatusField fields[] = {
    {"cpu average", "cpu_average_percent", "%", StatusKind::real, 1},
    {"cpu peak", "cpu_peak_percent", "%", StatusKind::real, 1},
    {"drops per second", "drops_per_second", "", StatusKind::real, 1},
    {"active drops, full tier", "active_drops_full", "", StatusKind::integer, 0},
    {"active drops, template tier", "active_drops_template", "", StatusKind::integer, 0},
    {"active drops, texture tier", "active_drops_texture", "", StatusKind::integer, 0},
    {"xruns", "xruns", "", StatusKind::integer, 0},
    {"late bundles", "late_bundles", "", StatusKind::integer, 0},
    {"sample rate", "sample_rate_hz", "Hz", StatusKind::real, 1},
    {"block size", "block_size_frames", "frames", StatusKind::integer, 0},
    {"audio rendered", "seconds_rendered", "s", StatusKind::real, 2},
    {"rain rate", "rain_rate_mm_per_h", "mm/h", StatusKind::real, 2},
    {"backend", "backend", "", StatusKind::text, 0},
    {"audio clock against the wall", "clock_ppm", "ppm", StatusKind::real, 1},
    {"clipped samples", "clipped_samples", "", StatusKind::integer, 0},
    {"full scale", "full_scale_db_spl", "dB SPL", StatusKind::real, 2},
};

// 29.874 with 2 decimals -> "29.87"; 30 -> "30"; 3.10 -> "3.1".
std::string fixed_trimmed(double v, int decimals) {
    if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
    std::string s = buffer;
    if (s.find('.') != std::string::npos) {
        s.erase(s.find_last_not_of('0') + 1);
        if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
}

// The value as the server's float carried it: 3.1f prints as 3.1, not 3.0999999046325684.
// JSON has no inf or nan, so those become null.
std::string json_real(double v) {
    if (!std::isfinite(v)) return "null";
    return shortest_float(static_cast<float>(v));
}

}  // namespace

std::span<const StatusField> status_fields() { return fields; }

StatusReport parse_status_reply(const protocol::DecodedMessage& message) {
    StatusReport r;
    const std::size_t expected = std::size(fields);
    if (message.args.size() < expected) {
        r.error = "the server's /status.reply has " + std::to_string(message.args.size()) + " fields (,"
                  + message.types + "), expected " + std::to_string(expected) + ": a different version of ameotod?";
        return r;
    }
    for (std::size_t i = 0; i < expected; ++i) {
        const protocol::OscArgument& a = message.args[i];
        const StatusField& f = fields[i];
        StatusValue v;
        if (f.kind == StatusKind::text) {
            if (a.type != 's' && a.type != 'S') {
                r.error = std::string("the server's /status.reply field ") + std::to_string(i + 1) + " (" + f.label +
                          ") is type '" + a.type + "', expected a string";
                r.values.clear();
                return r;
            }
            v.text = a.text;
        } else {
            if (!a.is_number()) {
                r.error = std::string("the server's /status.reply field ") + std::to_string(i + 1) + " (" + f.label +
                          ") is type '" + a.type + "', expected a number";
                r.values.clear();
                return r;
            }
            v.number = a.number;
            v.integer = (a.type == 'i' || a.type == 'h') ? a.integer : static_cast<std::int64_t>(std::llround(a.number));
        }
        r.values.push_back(std::move(v));
    }
    return r;
}

std::string format_status_text(const StatusReport& report) {
    std::string out;
    for (std::size_t i = 0; i < report.values.size() && i < std::size(fields); ++i) {
        const StatusField& f = fields[i];
        const StatusValue& v = report.values[i];
        out += std::string(f.label) + ": ";
        switch (f.kind) {
            case StatusKind::real: out += fixed_trimmed(v.number, f.decimals); break;
            case StatusKind::integer: out += std::to_string(v.integer); break;
            case StatusKind::text: out += v.text; break;
        }
        if (*f.unit) out += std::string(" ") + f.unit;
        out += '\n';
    }
    return out;
}

std::string format_status_json(const StatusReport& report) {
    std::string out = "{";
    for (std::size_t i = 0; i < report.values.size() && i < std::size(fields); ++i) {
        const StatusField& f = fields[i];
        const StatusValue& v = report.values[i];
        if (i > 0) out += ", ";
        out += json_string(f.json_key) + ": ";
        switch (f.kind) {
            case StatusKind::real: out += json_real(v.number); break;
            case StatusKind::integer: out += std::to_string(v.integer); break;
            case StatusKind::text: out += json_string(v.text); break;
        }
    }
    return out + "}\n";
}

}  // namespace ameoto::client
