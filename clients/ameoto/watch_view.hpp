// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What `ameoto watch` shows: the server's /meter levels as bars and its /status.reply load, either as
// a screen redrawn in place (a terminal) or as one line per update (a pipe, a log).
//
// Interface:
//   MeterReading m = parse_meter(message);            // m.error empty when the shape is right
//   WatchState s;  s.meter = m;  s.status = parse_status_reply(reply);
//   out << format_watch_screen(s);                    // lines for a terminal, redrawn in place
//   out << format_meter_line(m);                      // "meter t=1.000 1:-12.3/-20.1 2:..." + '\n'
//   out << format_status_line(report);                // "status cpu=3.1% peak=4.0% drops/s=..." + '\n'
//   meter_bar(-12.0, 30);                             // "[########################......]"
//
// /meter (docs/PROTOCOL.md): f seconds, i channels, then f peak and f RMS in dBFS per channel, then (from
// servers that measure it) f momentary and f short-term loudness (LUFS) and f true peak (dBTP).
// Bars span -60..0 dBFS (below -60 is empty: rain at a distance sits near -40, silence at -120).

#include <optional>
#include <string>
#include <vector>

#include "clients/ameoto/status_report.hpp"
#include "protocol/osc_codec.hpp"

namespace ameoto::client {

struct MeterReading {
    double seconds = 0.0;   // audio time at the window's end
    std::vector<double> peak_dbfs, rms_dbfs;   // one per channel
    std::optional<double> momentary_lufs, short_term_lufs, true_peak_dbtp;   // all or none
    std::string error;
};

struct WatchState {
    std::optional<MeterReading> meter;
    std::optional<StatusReport> status;
    std::string target;   // "127.0.0.1:7770", for the screen's title
};

constexpr double meter_floor_dbfs = -60.0;

MeterReading parse_meter(const protocol::DecodedMessage& message);
std::string meter_bar(double dbfs, int width);
std::string format_watch_screen(const WatchState& state);
std::string format_meter_line(const MeterReading& meter);
std::string format_status_line(const StatusReport& status);

}  // namespace ameoto::client
