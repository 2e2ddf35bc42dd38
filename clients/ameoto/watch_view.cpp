// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/watch_view.hpp"

#include <algorithm>
#include <cmath>

#include "clients/ameoto/number_text.hpp"

namespace ameoto::client {
namespace {

// Indices into StatusReport::values (status_fields(), the order the server sends them).
enum StatusIndex { cpu_average = 0, cpu_peak, drops_per_second, full, templ, texture, xruns, late, sample_rate, block, seconds, rain, backend, clock_ppm, clipped, full_scale };

double level(double dbfs) { return std::isfinite(dbfs) ? dbfs : -120.0; }

}  // namespace

MeterReading parse_meter(const protocol::DecodedMessage& m) {
    MeterReading r;
    if (m.args.size() < 2 || !m.args[0].is_number() || !m.args[1].is_number()) {
        r.error = "the server's /meter (," + m.types + ") does not start with a time and a channel count";
        return r;
    }
    const long long channels = m.args[1].integer;
    const std::size_t levels = 2 + 2 * static_cast<std::size_t>(channels < 0 ? 0 : channels);
    if (channels < 0 || channels > 64 || (m.args.size() != levels && m.args.size() != levels + 3)) {
        r.error = "the server's /meter (," + m.types + ") does not carry a peak and an RMS for each of its " + std::to_string(channels) +
                  " channels";
        return r;
    }
    r.seconds = m.args[0].number;
    for (long long c = 0; c < channels; ++c) {
        const auto& peak = m.args[2 + 2 * static_cast<std::size_t>(c)];
        const auto& rms = m.args[3 + 2 * static_cast<std::size_t>(c)];
        if (!peak.is_number() || !rms.is_number()) {
            r.error = "the server's /meter (," + m.types + ") has text where a level belongs";
            return r;
        }
        r.peak_dbfs.push_back(level(peak.number));
        r.rms_dbfs.push_back(level(rms.number));
    }
    if (m.args.size() == levels + 3) {
        for (std::size_t k = levels; k < levels + 3; ++k)
            if (!m.args[k].is_number()) {
                r.error = "the server's /meter (," + m.types + ") has text where a loudness belongs";
                return r;
            }
        r.momentary_lufs = level(m.args[levels].number);
        r.short_term_lufs = level(m.args[levels + 1].number);
        r.true_peak_dbtp = level(m.args[levels + 2].number);
    }
    return r;
}

std::string meter_bar(double dbfs, int width) {
    const double fraction = std::clamp((level(dbfs) - meter_floor_dbfs) / -meter_floor_dbfs, 0.0, 1.0);
    const int filled = static_cast<int>(std::lround(fraction * width));
    std::string bar(static_cast<std::size_t>(width) + 2, '.');   // built in place (GCC 12 warns on "[" + string)
    bar.front() = '[';
    bar.back() = ']';
    std::fill_n(bar.begin() + 1, filled, '#');
    return bar;
}

std::string format_meter_line(const MeterReading& meter) {
    std::string line = "meter t=";
    line += fixed(meter.seconds, 3);
    for (std::size_t c = 0; c < meter.peak_dbfs.size(); ++c) {
        line += ' ';
        line += std::to_string(c + 1);
        line += ':';
        line += fixed(meter.peak_dbfs[c], 1);
        line += '/';
        line += fixed(meter.rms_dbfs[c], 1);
    }
    line += " dBFS peak/rms";
    if (meter.momentary_lufs)
        line += " M=" + fixed(*meter.momentary_lufs, 1) + " S=" + fixed(*meter.short_term_lufs, 1) + " LUFS TP=" +
                fixed(*meter.true_peak_dbtp, 1) + " dBTP";
    line += "\n";
    return line;
}

std::string format_status_line(const StatusReport& s) {
    const auto& v = s.values;
    return "status cpu=" + fixed(v[cpu_average].number, 1) + "% peak=" + fixed(v[cpu_peak].number, 1) +
           "% drops/s=" + fixed(v[drops_per_second].number, 1) + " full=" + std::to_string(v[full].integer) +
           " template=" + std::to_string(v[templ].integer) + " texture=" + std::to_string(v[texture].integer) +
           " rain=" + fixed(v[rain].number, 2) + "mm/h xruns=" + std::to_string(v[xruns].integer) +
           " late=" + std::to_string(v[late].integer) + " backend=" + v[backend].text + "\n";
}

std::string format_watch_screen(const WatchState& state) {
    std::string out = "ameoto watch " + state.target + "  (Ctrl-C to quit)\n";
    if (state.status) {
        const auto& v = state.status->values;
        out += "load  " + fixed(v[cpu_average].number, 1) + " % average, " + fixed(v[cpu_peak].number, 1) + " % peak   xruns " +
               std::to_string(v[xruns].integer) + "   late bundles " + std::to_string(v[late].integer) + "\n";
        out += "rain  " + fixed(v[rain].number, 2) + " mm/h, " + fixed(v[drops_per_second].number, 1) + " drops/s   drops: " +
               std::to_string(v[full].integer) + " full, " + std::to_string(v[templ].integer) + " template, " +
               std::to_string(v[texture].integer) + " texture\n";
        out += "audio " + v[backend].text + ", " + fixed(v[sample_rate].number, 0) + " Hz, " + std::to_string(v[block].integer) +
               " frames a block, " + fixed(v[seconds].number, 1) +
               " s played, 0 dBFS = " + fixed(v[full_scale].number, 2) + " dB SPL, " + std::to_string(v[clipped].integer) +
               " samples past full scale\n";
    } else {
        out += "load  (waiting for the first /status.reply)\n\n\n";
    }
    if (state.meter) {
        for (std::size_t c = 0; c < state.meter->peak_dbfs.size(); ++c) {
            const double peak = state.meter->peak_dbfs[c], rms = state.meter->rms_dbfs[c];
            out += "ch " + std::to_string(c + 1) + (c + 1 < 10 ? " " : "") + " " + meter_bar(rms, 40) + " rms " + fixed(rms, 1) +
                   "  peak " + fixed(peak, 1) + " dBFS\n";
        }
        if (state.meter->momentary_lufs)
            out += "loud  " + meter_bar(*state.meter->momentary_lufs, 40) + " momentary " + fixed(*state.meter->momentary_lufs, 1) +
                   "  short-term " + fixed(*state.meter->short_term_lufs, 1) + " LUFS  true peak " +
                   fixed(*state.meter->true_peak_dbtp, 1) + " dBTP\n";
    } else {
        out += "(waiting for the first /meter)\n";
    }
    return out;
}

}  // namespace ameoto::client
