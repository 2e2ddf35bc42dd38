// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_report.hpp"

#include <cmath>

#include "clients/ameoto/number_text.hpp"

namespace ameoto::client {
namespace {

// number_text's fixed(), with "-" for a figure that could not be measured.
std::string fixed_or_dash(double value, int decimals) { return std::isfinite(value) ? fixed(value, decimals) : "-"; }

// Three significant digits, as plain decimals (the figures are good to about 1 %).
std::string figure(double value) {
    if (!std::isfinite(value)) return "-";
    const double a = std::fabs(value);
    return fixed_or_dash(value, a >= 100.0 ? 0 : a >= 10.0 ? 1 : a >= 1.0 ? 2 : 3);
}

std::string pad(const std::string& text, std::size_t width, bool right) {
    if (text.size() >= width) return text;
    const std::string space(width - text.size(), ' ');
    return right ? space + text : text + space;
}

}  // namespace

bool BenchMeasurement::measured() const { return std::isfinite(ns_per_sample) && ns_per_sample > 0.0; }

double BenchMeasurement::ns_per_mass_update() const {
    return masses > 0 ? ns_per_sample / (static_cast<double>(masses) * sub_steps) : NAN;
}

double BenchMeasurement::ns_per_link_update() const {
    return links > 0 ? ns_per_sample / (static_cast<double>(links) * sub_steps) : NAN;
}

double BenchMeasurement::core_percent() const { return 100.0 * ns_per_sample * 1e-9 * sample_rate_hz; }

double BenchMeasurement::realtime_factor() const { return 1e9 / (sample_rate_hz * ns_per_sample); }

std::string format_measurement_json(const BenchMeasurement& m) {
    const bool ok = m.measured();
    auto number = [&](double v) { return json_number(ok ? v : NAN); };
    auto optional = [&](const std::optional<double>& v) { return v ? json_number(*v) : std::string("null"); };
    std::string out = "{";
    out += "\"suite\":\"engine\"";
    out += ",\"mesh\":" + json_string(m.mesh);
    out += ",\"method\":" + json_string(m.method);
    out += ",\"body\":" + json_string(m.body);
    out += ",\"integrator\":" + json_string(m.integrator);
    out += ",\"precision\":" + json_string(m.precision);
    out += ",\"target_masses\":" + std::to_string(m.target_masses);
    out += ",\"masses\":" + std::to_string(m.masses);
    out += ",\"links\":" + std::to_string(m.links);
    out += ",\"sub_steps\":" + std::to_string(m.sub_steps);
    out += ",\"sample_rate_hz\":" + json_number(m.sample_rate_hz);
    out += ",\"ns_per_sample\":" + number(m.ns_per_sample);
    out += ",\"ns_per_sample_min\":" + number(m.ns_min);
    out += ",\"ns_per_sample_max\":" + number(m.ns_max);
    out += ",\"ns_per_mass_update\":" + number(m.ns_per_mass_update());
    out += ",\"ns_per_link_update\":" + number(m.ns_per_link_update());
    out += ",\"core_percent\":" + number(m.core_percent());
    out += ",\"realtime_factor\":" + number(m.realtime_factor());
    out += ",\"runs\":" + std::to_string(ok ? m.runs : 0);
    out += ",\"samples_per_run\":" + std::to_string(ok ? m.samples_per_run : 0);
    out += ",\"faust_ratio\":" + optional(m.faust_ratio);
    out += ",\"faust_difference\":" + optional(m.faust_difference);
    out += ",\"note\":" + json_string(m.note);
    return out + "}\n";
}

namespace {

constexpr std::size_t method_width = 34;
constexpr std::size_t number_width = 11;

}  // namespace

std::string format_table_header() {
    std::string line = pad("method", method_width, false);
    for (const char* title : {"masses", "links", "sub", "ns/sample", "ns/mass", "ns/link", "% core", "x realtime", "/ faust"})
        line += pad(title, number_width, true);
    return line + "\n" + std::string(line.size(), '-') + "\n";
}

std::string format_table_row(const BenchMeasurement& m) {
    std::string line = pad(m.method, method_width, false);
    line += pad(std::to_string(m.masses), number_width, true);
    line += pad(std::to_string(m.links), number_width, true);
    line += pad(std::to_string(m.sub_steps), number_width, true);
    if (m.measured()) {
        line += pad(figure(m.ns_per_sample), number_width, true);
        line += pad(figure(m.ns_per_mass_update()), number_width, true);
        line += pad(figure(m.ns_per_link_update()), number_width, true);
        line += pad(figure(m.core_percent()), number_width, true);
        line += pad(figure(m.realtime_factor()), number_width, true);
        line += pad(m.faust_ratio ? fixed_or_dash(*m.faust_ratio, 2) : std::string(), number_width, true);
    } else {
        line += "  not measured";
    }
    line += "\n";
    if (!m.note.empty()) line += "    " + m.note + "\n";
    return line;
}

}  // namespace ameoto::client
