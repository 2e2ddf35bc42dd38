// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "clients/ameoto/bench_accuracy_air.hpp"
#include "clients/ameoto/bench_accuracy_charts.hpp"
#include "clients/ameoto/bench_accuracy_drop.hpp"
#include "clients/ameoto/bench_accuracy_tiers.hpp"
#include "clients/ameoto/bench_drive.hpp"
#include "clients/ameoto/bench_suite_opening.hpp"
#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto::client {

namespace {


// What the scene does to a panel every sample under heavy rain: the template tier's force on one node
// (hopping over the panel by a prime stride; small, so the body stays linear), the step, and the far
// field's read of every node's velocity (FarFieldRadiation::process reads each panel node by node).
// Velocities and positions are stored by the step schemes and formed from the modes by the modal one
// (O(modes) each), so this read is where the modal scheme pays for its cheap step.
double drive_scene(TransverseNetwork& net, long samples, long& clock) {
    const int nodes = net.mass_count();
    double sum = 0.0;
    for (long n = 0; n < samples; ++n, ++clock) {
        net.apply_force(static_cast<int>((clock * 7919) % nodes), 1e-3);
        sum += net.step();
        for (int i = 0; i < nodes; ++i) sum += net.velocity(i);
    }
    return sum;
}

// A lattice drop near the panel (the full tier) adds the collider's broad phase: every node's
// displacement read each sample (Canopy::displacement_range).
double drive_contact(TransverseNetwork& net, long samples, long& clock) {
    const int nodes = net.mass_count();
    double sum = 0.0;
    for (long n = 0; n < samples; ++n, ++clock) {
        double highest = -1e300;
        for (int i = 0; i < nodes; ++i) highest = std::max(highest, net.position(i));
        net.apply_force(static_cast<int>((clock * 7919) % nodes), 1e-3);
        sum += net.step() + highest;
        for (int i = 0; i < nodes; ++i) sum += net.velocity(i);
    }
    return sum;
}

struct AccuracyOptions {
    bool json = false;
    double seconds = 0.3;
    int runs = 5;
    double air_reference_dx = 0.0;   // m; 0: the committed reference figures (bench_accuracy_air.cpp)
    std::string csv, svg, stability_svg, table;
};

const std::vector<MethodSetting>& settings() {
    static const std::vector<MethodSetting> s = {
        {Integrator::explicit_verlet, 1, 0},  {Integrator::explicit_verlet, 2, 0}, {Integrator::explicit_verlet, 4, 0},
        {Integrator::explicit_verlet, 8, 0},  {Integrator::symplectic_euler, 1, 0}, {Integrator::trapezoidal, 1, 0},
        {Integrator::backward_euler, 1, 0},   {Integrator::modal, 1, 8},            {Integrator::modal, 1, 16},
        {Integrator::modal, 1, 32},           {Integrator::modal, 1, 0},
    };
    return s;
}

// Returns false with the message in error.
bool parse(const CommandWords& words, AccuracyOptions& o, std::string& error, bool& help) {
    OptionReader reader(words);
    for (auto kind = reader.next_word(); kind != OptionReader::Word::end; kind = reader.next_word()) {
        if (kind == OptionReader::Word::positional) {
            if (reader.positional() == "accuracy") continue;
            error = "unexpected argument '" + reader.positional() + "'";
            return false;
        }
        const std::string& name = reader.name();
        if (name == "--help" || name == "-h") {
            help = true;
            return true;
        }
        if (name == "--json") {
            if (!reader.flag_into(error)) return false;
            o.json = true;
        } else if (name == "--seconds") {
            const auto v = reader.number_into(0.01, 600.0, "s", error);
            if (!v) return false;
            o.seconds = *v;
        } else if (name == "--runs") {
            const auto v = reader.number_into(1.0, 101.0, "runs", error);
            if (!v) return false;
            if (*v != std::floor(*v)) {
                error = "--runs: give a whole number of runs, 1..101";
                return false;
            }
            o.runs = static_cast<int>(*v);
        } else if (name == "--air-reference") {
            const auto v = reader.number_into(0.005, 0.05, "m", error);
            if (!v) return false;
            o.air_reference_dx = *v;
        } else if (name == "--csv" || name == "--svg" || name == "--stability-svg" || name == "--table") {
            std::string value;
            if (!reader.value_into(value, error)) return false;
            if (value.empty()) {
                error = name + ": give a file name";
                return false;
            }
            (name == "--csv" ? o.csv : name == "--svg" ? o.svg : name == "--table" ? o.table : o.stability_svg) = value;
        } else {
            error = "unknown option '" + name + "'";
            return false;
        }
    }
    return true;
}

std::string number(const char* f, double v) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, f, v);
    return buffer;
}

bool write_file(const std::string& path, const std::string& content, const CommandIo& io) {
    std::ofstream out(path, std::ios::binary);
    out << content;
    if (!out) {
        io.err << "ameoto bench: cannot write " << path << "\n";
        return false;
    }
    return true;
}

std::string csv(const std::vector<AccuracyRow>& rows) {
    std::string s = "body,method,integrator,sub_steps,modes,ns_per_sample,core_percent_48k,ns_per_sample_quiet,ns_per_sample_contact,cents,lsd_db,front_cents,front_db,ns_per_drop,level_db\n";
    for (const AccuracyRow& r : rows) {
        s += r.body + "," + method_label(r.method.setting) + "," + integrator_name(r.method.setting.integrator) + "," +
             std::to_string(r.errors.sub_steps) + "," + std::to_string(r.errors.modes_kept) + "," +
             number("%.1f", r.method.ns_per_sample) + "," + number("%.3f", r.core_percent()) + "," +
             number("%.1f", r.ns_quiet) + "," + number("%.1f", r.ns_contact) + "," + number("%.4g", r.method.cents) + "," + number("%.4g", r.method.decibels) + "," + (r.front_cents ? "yes" : "no") +
             "," + (r.front_decibels ? "yes" : "no") + ",,\n";
    }
    return s;
}

// The canopy in air against the FDTD reference (bench_accuracy_air.hpp): cost per sample of the whole
// canopy, cents = the worst of the first 10 panel modes against the reference's.
std::string air_csv(const std::vector<AirRow>& rows) {
    std::string s;
    for (const AirRow& r : rows)
        s += "canopy in air," + r.label + "," + r.kind + "," + std::to_string(r.sub_steps) + "," + std::to_string(r.modes) + "," +
             number("%.1f", r.ns_per_sample) + "," + number("%.3f", r.core_percent()) + ",,," + number("%.4g", r.errors.worst) + ",," +
             (r.front ? "yes" : "no") + ",no,,\n";
    return s;
}

std::string air_json(const AirRow& r) {
    std::string hz, cents;
    for (std::size_t q = 0; q < r.mode_hz.size(); ++q) {
        if (q) hz += ',', cents += ',';
        hz += json_number(r.mode_hz[q]);
        cents += json_number(r.errors.cents[q]);
    }
    return "{\"suite\":\"accuracy\",\"body\":\"canopy in air\",\"method\":" + json_string(r.label) + ",\"kind\":" + json_string(r.kind) +
           ",\"sub_steps\":" + std::to_string(r.sub_steps) + ",\"modes\":" + std::to_string(r.modes) +
           ",\"ns_per_sample\":" + json_number(r.ns_per_sample) + ",\"core_percent\":" + json_number(r.core_percent()) +
           ",\"cents\":" + json_number(r.errors.worst) + ",\"mode_hz\":[" + hz + "],\"mode_cents\":[" + cents +
           "],\"front_cents\":" + (r.front ? "true" : "false") + "}\n";
}

std::string air_table_row(const AirRow& r) {
    char line[320];
    std::snprintf(line, sizeof line, "%-34s %11.1f %8.3f %9.4g %8.4g %8.4g%s\n", r.label.c_str(), r.ns_per_sample, r.core_percent(),
                  r.errors.worst, r.errors.cents.empty() ? 0.0 : r.errors.cents.front(),
                  r.errors.cents.size() > 3 ? r.errors.cents[3] : 0.0, r.front ? "  front(cents)" : "");
    return line;
}

// The drop tiers' cost is per drop (its whole life), not per sample: a column of its own, ns_per_drop.
bool on_tier_front(const TierRow& r, const std::vector<TierRow>& rows) {
    const auto cost = [](const TierRow& t) { return std::max(t.ns_per_drop, 0.0); };   // under the noise: 0
    for (const TierRow& o : rows)
        if (cost(o) <= cost(r) && o.lsd_db <= r.lsd_db && (cost(o) < cost(r) || o.lsd_db < r.lsd_db)) return false;
    return true;
}

std::string tiers_csv(const std::vector<TierRow>& rows) {
    std::string s;
    for (const TierRow& r : rows)
        s += "drop tiers," + r.name + ",level of detail,,,,,,,," + number("%.4g", r.lsd_db) + ",," + (on_tier_front(r, rows) ? "yes" : "no") +
             "," + number("%.0f", r.ns_per_drop) + "," + number("%.3f", r.level_db) + "\n";
    return s;
}

std::string json(const AccuracyRow& r) {
    return "{\"suite\":\"accuracy\",\"body\":" + json_string(r.body) + ",\"method\":" + json_string(method_label(r.method.setting)) +
           ",\"integrator\":" + json_string(integrator_name(r.method.setting.integrator)) +
           ",\"sub_steps\":" + std::to_string(r.errors.sub_steps) + ",\"modes\":" + std::to_string(r.errors.modes_kept) +
           ",\"ns_per_sample\":" + json_number(r.method.ns_per_sample) + ",\"core_percent\":" + json_number(r.core_percent()) + ",\"ns_per_sample_quiet\":" + json_number(r.ns_quiet) +
           ",\"ns_per_sample_contact\":" + json_number(r.ns_contact) +
           ",\"cents\":" + json_number(r.method.cents) + ",\"lsd_db\":" + json_number(r.method.decibels) +
           ",\"front_cents\":" + (r.front_cents ? "true" : "false") + ",\"front_db\":" + (r.front_decibels ? "true" : "false") +
           "}\n";
}

std::string table_row(const AccuracyRow& r) {
    char line[256];
    std::snprintf(line, sizeof line, "%-22s %9d %6d %10.1f %7.3f %8.1f %8.1f %10.4g %9.4g  %s%s\n", method_label(r.method.setting).c_str(),
                  r.errors.sub_steps, r.errors.modes_kept, r.method.ns_per_sample, r.core_percent(), r.ns_quiet, r.ns_contact, r.method.cents,
                  r.method.decibels, r.front_cents ? "front(cents) " : "", r.front_decibels ? "front(dB)" : "");
    return line;
}

// 4 significant digits rounded up: the table never claims a method more accurate than it measured.
std::string cpp_number(double v) {
    if (!std::isfinite(v)) return "inf";
    if (v <= 0.0) return "0";
    const double unit = std::pow(10.0, std::floor(std::log10(v)) - 3.0);
    return number("%.4g", std::ceil(v / unit * (1.0 - 1e-12)) * unit);
}

// method_table.cpp: the knob's data, as the engine compiles it.
std::string table_source(const std::vector<AccuracyRow>& rows, const std::string& machine) {
    std::string s =
        "// Generated by `ameoto bench accuracy --table engine/core/method_table.cpp` (clients/ameoto/bench_accuracy.cpp):\n"
        "// the default umbrella panel (50 masses, nylon, 48 kHz); cost in ns per output sample of one panel in the\n"
        "// scene under heavy rain (a force every sample, the far field reading every node's velocity),\n"
        "// errors against the exact modal solution (docs/accuracy.md). Regenerate, do not edit by hand.\n"
        "#include \"engine/core/method_choice.hpp\"\n\n"
        "#include <limits>\n\n"
        "namespace ameoto {\n\n"
        "namespace {\n\n"
        "constexpr double inf = std::numeric_limits<double>::infinity();   // a mode the method leaves out\n\n"
        "constexpr MeasuredMethod table[] = {\n";
    const char* names[] = {"explicit_verlet", "symplectic_euler", "trapezoidal", "backward_euler", "modal"};
    for (const AccuracyRow& r : rows) {
        const MethodSetting& m = r.method.setting;
        s += "    {{Integrator::" + std::string(names[static_cast<int>(m.integrator)]) + ", " + std::to_string(m.sub_steps) + ", " +
             std::to_string(m.modes) + "}, " + number("%.1f", r.method.ns_per_sample) + ", " + cpp_number(r.method.cents) +
             ", " + cpp_number(r.method.decibels) + "},\n";
    }
    s += "};\n\n}  // namespace\n\n"
         "std::span<const MeasuredMethod> measured_methods() { return table; }\n\n"
         "const char* measured_methods_source() {\n"
         "    return \"ameoto bench accuracy --table engine/core/method_table.cpp (" + machine + ")\";\n"
         "}\n\n}  // namespace ameoto\n";
    return s;
}

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

std::vector<double> omega_t_grid() {
    std::vector<double> x;
    for (int i = 0; i <= 24; ++i) x.push_back(0.1 * std::pow(100.0, i / 24.0));   // 0.1..10, log-spaced
    return x;
}

}  // namespace

AccuracyRow measure_method(const BenchMesh& mesh, const MethodSetting& setting, const AccuracyReference& reference,
                           double seconds, int runs) {
    AccuracyRow r;
    r.body = mesh.name;
    r.method.setting = setting;
    r.errors = measure_errors(mesh, setting, reference);
    r.method.cents = r.errors.cents;
    r.method.decibels = r.errors.decibels;
    TransverseNetwork net = build_network(mesh, setting);
    long clock = 0;
    r.ns_quiet = time_per_sample([&](long n) { bench_sink = bench_sink + drive_impulses(net, mesh.excite_node, n, clock); }, seconds, runs).median_ns;
    net.reset();
    r.method.ns_per_sample = time_per_sample([&](long n) { bench_sink = bench_sink + drive_scene(net, n, clock); }, seconds, runs).median_ns;
    net.reset();
    r.ns_contact = time_per_sample([&](long n) { bench_sink = bench_sink + drive_contact(net, n, clock); }, seconds, runs).median_ns;
    return r;
}

std::string accuracy_bench_usage() {
    return "usage: ameoto bench accuracy [--json] [--seconds S] [--runs R] [--csv FILE] [--svg FILE]\n"
           "                             [--stability-svg FILE] [--table FILE] [--air-reference DX]\n"
           "\n"
           "Speed against accuracy of every integration method on the default umbrella's panel (50 masses,\n"
           "nylon, 48 kHz): explicit Verlet at 1x, 2x, 4x, 8x sub-steps, symplectic Euler, trapezoidal,\n"
           "backward Euler, modal with 8, 16, 32 and all audible modes. Cost: ns per output sample of one\n"
           "panel and % of one core at 48 kHz (thread CPU time, median of runs). Errors against the exact\n"
           "modal solution: the largest frequency error of the audible modes below 5 kHz (cents) and the\n"
           "log-spectral distance of the impulse response, 20 Hz..20 kHz (dB). Then the canopy in air, held\n"
           "to the FDTD reference (engine/reference/, its committed 5 mm figures): the reference's own cost,\n"
           "the air-loaded modal canopy and every method above in vacuum, each by the worst error in cents of\n"
           "the struck panel's first 10 modes in air. Then a free 3 mm drop in\n"
           "explicit Verlet and symplectic Euler at 1x..8x its sub-steps (cost, cents). Then the stability map:\n"
           "growth factor per step against omega_max T (0.1..10) on an 8-mass chain, with the bound. Also the\n"
           "scene's drop tiers (full, template, texture): CPU per drop against the dry scene, and the\n"
           "third-octave long-term spectrum against the full tier's for the same rain (0.1 mm/h, 4 s);\n"
           "tier costs: min(R, 5) pairs of 3 S of audio (at most 4 s), the median.\n"
           "\n"
           "Options:\n"
           "  --json                one JSON object per method, one per line\n"
           "  --seconds S           CPU time spent timing each method, 0.01..600 (default 0.3)\n"
           "  --runs R              timed runs per method, 1..101; the median is reported (default 5)\n"
           "  --csv FILE            write the rows as CSV (docs/accuracy.csv)\n"
           "  --svg FILE            write the cost/error chart with the Pareto fronts (docs/accuracy.svg)\n"
           "  --stability-svg FILE  write the stability map (docs/stability.svg)\n"
           "  --table FILE          write the knob's data as C++ (engine/core/method_table.cpp)\n"
           "  --air-reference DX    recompute the FDTD reference in air at grid step DX (m, 0.005..0.05)\n"
           "                        instead of its committed figures (0.005: 9 minutes of CPU)\n"
           "\n"
           "Exit status: 0 measured; 1 a file could not be written; 2 usage error.\n"
           "\n"
           "Example (what docs/accuracy.md commits):\n"
           "  ameoto bench accuracy --seconds 1 --runs 9 --csv docs/accuracy.csv --svg docs/accuracy.svg \\\n"
           "      --stability-svg docs/stability.svg --table engine/core/method_table.cpp\n";
}

int run_accuracy_bench(const CommandWords& words, const CommandIo& io) {
    AccuracyOptions o;
    if (const auto done = open_bench_suite(words, io, "accuracy", o, parse, accuracy_bench_usage)) return *done;
    const BenchMesh mesh = canopy_panel_mesh(CanopyGeometry{}.masses_per_panel);
    io.err << "ameoto bench: the exact reference (modal, every audible mode) on the " << mesh.nodes.size() << "-mass panel\n";
    const AccuracyReference reference = make_reference(mesh, pitch_band_hz);
    if (!o.json) {
        io.out << "canopy panel (" << mesh.nodes.size() << " masses, nylon, 48 kHz); its " << reference.mode_hz.size()
               << " audible modes below " << number("%.0f", pitch_band_hz) << " Hz:";
        for (double hz : reference.mode_hz) io.out << " " << number("%.1f", hz);
        io.out << " Hz\n"
               << "ns/sample: in the scene under heavy rain (a force every sample, the far field reading every\n"
               << "node's velocity); quiet: the step alone, 1 N every 0.1 s (as bench engine); contact: a lattice\n"
               << "drop near as well (every node's displacement read each sample)\n"
               << "method                 sub-steps  modes  ns/sample  % core    quiet  contact      cents    LSD dB\n";
    }
    std::vector<AccuracyRow> rows;
    for (const MethodSetting& s : settings()) {
        io.err << "ameoto bench: " << method_label(s) << "\n" << std::flush;
        rows.push_back(measure_method(mesh, s, reference, o.seconds, o.runs));
    }
    std::vector<MeasuredMethod> methods;
    for (const AccuracyRow& r : rows) methods.push_back(r.method);
    for (AccuracyRow& r : rows) {
        for (const MeasuredMethod& f : pareto_front(methods, AccuracyMeasure::cents)) r.front_cents |= f.setting == r.method.setting;
        for (const MeasuredMethod& f : pareto_front(methods, AccuracyMeasure::decibels)) r.front_decibels |= f.setting == r.method.setting;
        io.out << (o.json ? json(r) : table_row(r));
    }
    // The canopy in air, held to the FDTD reference (bench_accuracy_air.hpp).
    AirReference air_reference = cached_air_reference();
    if (o.air_reference_dx > 0.0) {
        io.err << "ameoto bench: the FDTD reference in air at dx " << number("%.4g", o.air_reference_dx * 1e3)
               << " mm (9 minutes at 5 mm)\n" << std::flush;
        air_reference = compute_air_reference(o.air_reference_dx);
    }
    io.err << "ameoto bench: the canopy in air: the FDTD reference's cost, the air-loaded model, the in-vacuum methods\n" << std::flush;
    AirRowOptions air_options;
    air_options.seconds = o.seconds;
    air_options.runs = o.runs;
    const std::vector<AirRow> air_rows = measure_air_rows(air_reference, rows, reference, air_options);
    if (!o.json) {
        io.out << "\ncanopy in air (8 panels), against the FDTD reference (" << air_reference.source << "): the struck panel's first "
               << air_panel_modes << " modes,\neach its velocity projected on a vacuum mode shape and peaked, for every row alike;"
               << " cents = the worst |1200 log2(f / f_ref)|;\nns/sample: the whole canopy per 48 kHz output sample (reference: thread CPU"
               << " at its dx, set-up excluded;\nthe others as the scene drives them under heavy rain, the radiator's own work not counted)\n"
               << "reference Hz:";
        for (double hz : air_reference.mode_hz) io.out << " " << number("%.1f", hz);
        io.out << "\nrow                                  ns/sample   % core     cents  mode 1 c mode 4 c\n";
    }
    for (const AirRow& r : air_rows) io.out << (o.json ? air_json(r) : air_table_row(r));
    // The free drop: its own schemes (Body3D: explicit Verlet, symplectic Euler) and sub-steps.
    io.err << "ameoto bench: the free drop's reference (symplectic Euler, 64x the sub-steps it needs)\n" << std::flush;
    const double drop_reference_hz = drop_frequency(Integrator::symplectic_euler, 64);
    std::string drop_csv;
    if (!o.json)
        io.out << "\nfree drop (3 mm water, 1 % stretch, no gravity): n = 2 oscillation " << number("%.3f", drop_reference_hz)
               << " Hz converged\nmethod                 sub-steps  ns/sample   % core      cents\n";
    for (Integrator i : {Integrator::explicit_verlet, Integrator::symplectic_euler}) {
        for (int factor : {1, 2, 4, 8}) {
            const DropAccuracy d = measure_drop(i, factor, drop_reference_hz, o.seconds, o.runs);
            const std::string label = std::string(integrator_name(i)) + " " + std::to_string(factor) + "x";
            const double core = d.ns_per_sample * 48000.0 * 1e-9 * 100.0;
            drop_csv += "free drop," + label + "," + integrator_name(i) + "," + std::to_string(d.sub_steps) + ",0," +
                        number("%.1f", d.ns_per_sample) + "," + number("%.3f", core) + ",,," + number("%.4g", d.cents) + ",,,\n";
            if (o.json) {
                io.out << "{\"suite\":\"accuracy\",\"body\":\"free drop\",\"method\":" << json_string(label)
                       << ",\"integrator\":" << json_string(integrator_name(i)) << ",\"sub_steps\":" << d.sub_steps
                       << ",\"ns_per_sample\":" << json_number(d.ns_per_sample) << ",\"core_percent\":" << json_number(core)
                       << ",\"cents\":" << json_number(d.cents) << ",\"lsd_db\":null}\n";
            } else {
                char line[160];
                std::snprintf(line, sizeof line, "%-22s %9d %10.1f %8.3f %10.4g\n", label.c_str(), d.sub_steps, d.ns_per_sample,
                              core, d.cents);
                io.out << line;
            }
        }
    }
    // The scene's levels of detail (bench_accuracy_tiers.hpp): CPU per drop and the long-term spectrum
    // against the full tier's for the same rain.
    TierOptions tier_options;
    // The template's and the texture's cost per drop is near the machine's noise (the dry scene's CPU
    // varies by 10-20 % between runs here): long runs, the median of up to 5 pairs.
    tier_options.cost_seconds = std::clamp(3.0 * o.seconds, 0.5, 4.0);
    tier_options.runs = std::min(o.runs, 5);
    io.err << "ameoto bench: the drop tiers (full, template, texture: the same rain at " << tier_options.error_rate_mm_per_h
           << " mm/h for " << tier_options.error_seconds << " s, then each tier timed)\n" << std::flush;
    const std::vector<TierRow> tiers = measure_tiers(tier_options);
    if (!o.json)
        io.out << "\ndrop tiers (umbrella scene, 48 kHz stereo): error = third-octave long-term spectrum 25 Hz..20 kHz against the\n"
               << "full tier's for the same " << number("%.1f", tier_options.error_rate_mm_per_h) << " mm/h rain over "
               << number("%.0f", tier_options.error_seconds) << " s (texture: statistics only, not waveforms);\n"
               << "cost = CPU per drop over its life against the dry scene (full at " << number("%.1f", tier_options.error_rate_mm_per_h)
               << " mm/h, the others at 200 mm/h)\n"
               << "tier        CPU ns/drop    LSD dB  level dB   drops  not in tier (error run, cost runs)\n";
    for (const TierRow& t : tiers) {
        if (o.json) {
            io.out << "{\"suite\":\"accuracy\",\"body\":\"drop tiers\",\"method\":" << json_string(t.name)
                   << ",\"ns_per_drop\":" << json_number(t.ns_per_drop) << ",\"cost_rain_mm_per_h\":" << json_number(t.rate_mm_per_h)
                   << ",\"lsd_db\":" << json_number(t.lsd_db) << ",\"level_db\":" << json_number(t.level_db)
                   << ",\"drops\":" << t.drops << ",\"fallbacks\":" << t.fallbacks << ",\"cost_fallbacks\":" << t.cost_fallbacks
                   << ",\"front_db\":" << (on_tier_front(t, tiers) ? "true" : "false") << "}\n";
        } else {
            char line[200];
            std::snprintf(line, sizeof line, "%-10s %12.0f %9.3f %9.3f %7llu %7llu, %llu%s\n", t.name.c_str(), t.ns_per_drop, t.lsd_db,
                          t.level_db, static_cast<unsigned long long>(t.drops), static_cast<unsigned long long>(t.fallbacks),
                          static_cast<unsigned long long>(t.cost_fallbacks),
                          t.ns_per_drop <= 0.0 ? "  (cost under the machine's noise)" : "");
            io.out << line;
        }
    }
    bool written = true;
    if (!o.csv.empty()) written &= write_file(o.csv, csv(rows) + air_csv(air_rows) + drop_csv + tiers_csv(tiers), io);
    if (!o.table.empty()) written &= write_file(o.table, table_source(rows, cpu_model()), io);
    if (!o.svg.empty()) {
        LogPanel cents, db;
        cents.y_label = "largest frequency error of the audible modes below 5 kHz, cents";
        db.y_label = "log-spectral distance of the impulse response, dB";
        for (const AccuracyRow& r : rows) {
            cents.points.push_back({method_label(r.method.setting), r.method.ns_per_sample, r.method.cents, r.front_cents, ""});
            db.points.push_back({method_label(r.method.setting), r.method.ns_per_sample, r.method.decibels, r.front_decibels, ""});
        }
        cents.heading = "umbrella panel (50 masses, nylon): frequency";
        db.heading = "umbrella panel (50 masses, nylon): spectrum";
        // The tiers: cost per drop, error against the full tier (the reference, drawn at the floor).
        LogPanel tier_panel;
        tier_panel.y_label = "long-term spectrum against the full tier, dB (third octaves)";
        tier_panel.floor = 1e-2;
        tier_panel.x_label = "cost, CPU ns per drop over its life (log)";
        tier_panel.floor_note = "at the floor with an arrow: full, the reference (0 by definition)";
        tier_panel.heading = "drop tiers (umbrella scene): texture compared as statistics only";
        constexpr double tier_cost_floor_ns = 10.0;   // a cost under the machine's noise is drawn here
        for (const TierRow& t : tiers)
            tier_panel.points.push_back({t.ns_per_drop > 0.0 ? t.name : t.name + " (cost < noise)", std::max(t.ns_per_drop, tier_cost_floor_ns),
                                         t.lsd_db, on_tier_front(t, tiers), ""});
        // The canopy in air: cost of the whole canopy, error against the FDTD reference (drawn at the floor).
        LogPanel air_panel;
        air_panel.y_label = "worst error of panel modes 1-10 against the FDTD reference, cents";
        air_panel.x_label = "cost, ns per output sample of the whole canopy, 8 panels (log)";
        air_panel.floor = 1e-1;
        air_panel.floor_note = "at the floor with an arrow: the FDTD reference (0 by definition)";
        air_panel.heading = "canopy in air: held to the FDTD reference (air-loaded: orange; in vacuum: blue)";
        // The in-vacuum rows all sit within a few cents of each other (the air's shift dwarfs every
        // method's own error): one label names the cluster, at its cheapest finite point.
        const AirRow* cheapest_vacuum = nullptr;
        double vacuum_low = 1e300, vacuum_high = 0.0;
        int vacuum_count = 0;
        for (const AirRow& r : air_rows)
            if (r.kind == "vacuum" && std::isfinite(r.errors.worst)) {
                if (!cheapest_vacuum || r.ns_per_sample < cheapest_vacuum->ns_per_sample) cheapest_vacuum = &r;
                vacuum_low = std::min(vacuum_low, r.errors.worst);
                vacuum_high = std::max(vacuum_high, r.errors.worst);
                ++vacuum_count;
            }
        for (const AirRow& r : air_rows) {
            std::string label = r.label;
            if (r.kind == "vacuum" && std::isfinite(r.errors.worst))
                label = &r == cheapest_vacuum ? "in vacuum: " + std::to_string(vacuum_count) + " methods, " + number("%.0f", vacuum_low) + "-" +
                                                    number("%.0f", vacuum_high) + " cents"
                                              : "";
            air_panel.points.push_back({label, r.ns_per_sample, r.errors.worst, r.front, r.kind == "air" ? "#ff7f0e" : ""});
        }
        written &= write_file(o.svg, cost_error_chart("Cost against error: the umbrella panel's methods (48 kHz), the canopy in air, and the scene's drop tiers",
                                                      {cents, db, air_panel, tier_panel}), io);
    }
    // The stability map.
    const std::vector<double> grid = omega_t_grid();
    std::vector<StabilitySeries> series;
    for (Integrator i : {Integrator::explicit_verlet, Integrator::symplectic_euler, Integrator::trapezoidal,
                         Integrator::backward_euler, Integrator::modal}) {
        StabilitySeries s{integrator_name(i), grid, {}, {}};
        for (double x : grid) {
            s.measured.push_back(growth_factor(i, x));
            s.theory.push_back(theoretical_growth(i, x));
        }
        series.push_back(std::move(s));
    }
    if (!o.json) {
        io.out << "\nstability map: amplitude growth factor per step, 8-mass chain (omega_max T; bound in brackets)\n";
        for (std::size_t g = 0; g < grid.size(); g += 4) {
            io.out << number("omega_max T = %6.3f:", grid[g]);
            for (const StabilitySeries& s : series)
                io.out << "  " << s.name << " " << number("%.4g", s.measured[g]) << " [" << number("%.4g", s.theory[g]) << "]";
            io.out << "\n";
        }
    } else {
        for (const StabilitySeries& s : series)
            for (std::size_t g = 0; g < grid.size(); ++g)
                io.out << "{\"suite\":\"accuracy\",\"map\":\"stability\",\"integrator\":" << json_string(s.name)
                       << ",\"omega_max_t\":" << json_number(grid[g]) << ",\"growth\":" << json_number(s.measured[g])
                       << ",\"bound\":" << json_number(s.theory[g]) << "}\n";
    }
    if (!o.stability_svg.empty())
        written &= write_file(o.stability_svg,
                              stability_chart("Stability map: growth per step against omega_max T (8-mass chain)", series), io);
    return written ? exit_status::ok : exit_status::refused;
}

}  // namespace ameoto::client
