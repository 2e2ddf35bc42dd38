// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_engine.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sched.h>
#include <thread>

#include "clients/ameoto/bench_faust.hpp"
#include "clients/ameoto/bench_mesh.hpp"
#include "clients/ameoto/bench_methods.hpp"
#include "clients/ameoto/bench_report.hpp"
#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"

// AMEOTO_CXX_COMPILER and AMEOTO_CXX_FLAGS come from clients/ameoto/CMakeLists.txt: the compiler and
// flags ameoto itself was built with, so the Faust peer is compiled the same way.

namespace ameoto::client {
namespace {


std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

// Every measurement, ameoto's and Faust's (a child process inherits the mask), on one CPU; the
// previous mask comes back when the benchmark ends. cpu() is -1 when the system would not pin.
class CpuPin {
public:
    CpuPin() {
        const int cpu = sched_getcpu();
        if (cpu < 0 || sched_getaffinity(0, sizeof saved_, &saved_) != 0) return;
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpu, &one);
        if (sched_setaffinity(0, sizeof one, &one) == 0) cpu_ = cpu;
    }
    ~CpuPin() {
        if (cpu_ >= 0) sched_setaffinity(0, sizeof saved_, &saved_);
    }
    CpuPin(const CpuPin&) = delete;
    CpuPin& operator=(const CpuPin&) = delete;
    int cpu() const { return cpu_; }

private:
    cpu_set_t saved_{};
    int cpu_ = -1;
};

BenchMeasurement describe(const BenchMesh& mesh, const BenchMethod& method, int target) {
    BenchMeasurement m;
    m.mesh = mesh.name;
    m.method = method.name();
    m.body = method.body;
    m.integrator = method.integrator;
    m.precision = method.precision;
    m.target_masses = target;
    m.masses = static_cast<int>(mesh.nodes.size());
    m.links = static_cast<int>(mesh.links.size() + mesh.anchors.size());
    m.ns_per_sample = NAN;
    return m;
}

void record(BenchMeasurement& m, const BenchTiming& t) {
    m.ns_per_sample = t.median_ns;
    m.ns_min = t.min_ns;
    m.ns_max = t.max_ns;
    m.runs = t.runs;
    m.samples_per_run = t.samples_per_run;
}

class Printer {
public:
    Printer(const BenchOptions& options, const CommandIo& io) : json_(options.json), io_(io) {}
    void text(const std::string& s) {
        if (!json_) io_.out << s << std::flush;
    }
    void measurement(const BenchMeasurement& m) {
        io_.out << (json_ ? format_measurement_json(m) : format_table_row(m)) << std::flush;
    }
    void progress(const std::string& s) { io_.err << "ameoto bench: " << s << "\n" << std::flush; }

private:
    bool json_;
    const CommandIo& io_;
};

// The fastest measurement at each panel size, for the summary.
std::vector<BenchMeasurement> bench_panels(const BenchOptions& options, Printer& print) {
    std::vector<BenchMeasurement> fastest;
    for (const int size : options.sizes) {
        const BenchMesh mesh = canopy_panel_mesh(size);
        print.text("\ncanopy panel, about " + std::to_string(size) + " masses (nylon, 48 kHz; 1 N every 0.1 s): " +
                   std::to_string(mesh.nodes.size()) + " masses, " + std::to_string(mesh.links.size()) + " links, " +
                   std::to_string(mesh.anchors.size()) + " anchored masses\n");
        print.text(format_table_header());
        std::optional<BenchMeasurement> best;
        for (const BenchMethod& method : bench_methods()) {
            BenchMeasurement m = describe(mesh, method, size);
            m.sample_rate_hz = bench_sample_rate;
            if (!method.fits(mesh)) {
                m.note = "skipped: " + method.limit_reason;
                print.measurement(m);
                continue;
            }
            try {
                auto body = method.build(mesh);
                m.sub_steps = body->sub_steps();
                long clock = 0;
                record(m, time_per_sample([&](long n) { bench_sink = bench_sink + body->impulses(n, clock); }, options.seconds, options.runs));
            } catch (const std::exception& e) {
                m.note = std::string("refused: ") + e.what();
            }
            print.measurement(m);
            if (m.measured() && (!best || m.ns_per_sample < best->ns_per_sample)) best = m;
        }
        if (best) fastest.push_back(*best);
    }
    return fastest;
}

std::vector<double> render_pluck(BenchBody& body, long samples) {
    std::vector<double> y(static_cast<std::size_t>(samples));
    PluckDrive drive;
    body.pluck(samples, drive, y.data());
    return y;
}

std::string scientific(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1e", v);
    return buffer;
}

// Returns the fastest method's ratio to Faust (measured rows only), or why there is none.
struct FaustResult {
    std::optional<BenchMeasurement> fastest;
    std::string problem;
};

// Faust is timed before and after ameoto's rows (same CPU: the process is pinned, and the child
// inherits it) and its figure is the mean of the two medians, so a slow drift of the shared machine
// weighs on both sides alike; the rows are printed once the ratios are known.
FaustResult bench_triangle(const BenchOptions& options, Printer& print) {
    const BenchMesh mesh = mi_triangle_mesh();
    print.text("\nmi-faust triangleMesh.dsp (52 masses and 3 fixed corners, 129 links and 6 anchors; the .dsp's "
               "pluck; one sample = one step):\n");

    std::optional<FaustPeer> peer;
    std::optional<std::vector<double>> faust_output;
    BenchMeasurement faust;
    faust.mesh = mesh.name;
    faust.method = "faust mi.lib (generated C++)";
    faust.body = "faust";
    faust.integrator = "explicit Verlet";
    faust.precision = "double";
    faust.masses = static_cast<int>(mesh.nodes.size());
    faust.links = static_cast<int>(mesh.links.size() + mesh.anchors.size());
    faust.ns_per_sample = NAN;
    std::string error;
    auto time_faust = [&]() -> std::optional<BenchTiming> {
        if (!faust_output) return std::nullopt;
        return peer->time(options.seconds, options.runs, error);
    };
    if (!options.faust) {
        faust.note = "not compared (--no-faust)";
    } else {
        print.progress("compiling Faust's triangleMesh.dsp (faust -double, then the C++ compiler)...");
        peer.emplace(FaustPeer::prepare());
        if (!peer->ready()) faust.note = peer->problem();
        else faust_output = peer->dump(check_samples, error);
    }
    const std::optional<BenchTiming> before = time_faust();

    std::vector<BenchMeasurement> rows;
    std::string differences;
    for (const BenchMethod& method : bench_methods()) {
        BenchMeasurement m = describe(mesh, method, 0);
        m.sample_rate_hz = bench_sample_rate;
        try {
            if (faust_output) {
                auto check = method.build(mesh);
                m.faust_difference = max_relative_difference(render_pluck(*check, check_samples), *faust_output);
                differences += "  " + m.method + ": " + scientific(*m.faust_difference) + "\n";
            }
            auto body = method.build(mesh);
            m.sub_steps = body->sub_steps();
            PluckDrive drive;
            record(m, time_per_sample([&](long n) { bench_sink = bench_sink + body->pluck(n, drive, nullptr); }, options.seconds, options.runs));
        } catch (const std::exception& e) {
            m.note = std::string("refused: ") + e.what();
        }
        rows.push_back(m);
    }

    const std::optional<BenchTiming> after = before ? time_faust() : std::nullopt;
    if (before && after) {
        faust.ns_per_sample = 0.5 * (before->median_ns + after->median_ns);
        faust.ns_min = std::min(before->min_ns, after->min_ns);
        faust.ns_max = std::max(before->max_ns, after->max_ns);
        faust.runs = before->runs + after->runs;
        faust.samples_per_run = before->samples_per_run;
        faust.note = peer->faust_version() + "; " + peer->compile_command() + "; " + peer->dsp_path();
    } else if (peer && peer->ready()) {
        faust.note = error;
    }

    FaustResult result;
    print.text(format_table_header());
    print.measurement(faust);
    for (BenchMeasurement& m : rows) {
        if (faust.measured() && m.measured()) {
            m.faust_ratio = m.ns_per_sample / faust.ns_per_sample;
            if (!result.fastest || *m.faust_ratio < *result.fastest->faust_ratio) result.fastest = m;
        }
        print.measurement(m);
    }
    if (!faust.measured()) {
        result.problem = faust.note;
        print.text("\n" + faust.note + "\n");
        return result;
    }
    print.text("\nSame model: largest |ameoto - Faust| over the first " + std::to_string(check_samples) +
               " samples, relative to Faust's peak\n(explicit Verlet is mi.lib's scheme; the other integrators differ by "
               "their own discretisation):\n" +
               differences);
    return result;
}

void summary(const std::vector<BenchMeasurement>& panels, const FaustResult& faust, Printer& print) {
    char line[512];
    print.text("\nTargets:\n");
    if (faust.fastest) {
        std::snprintf(line, sizeof line, "  at most half of Faust's cost per sample on its triangle mesh: %s at %.2f (%s)\n",
                      faust.fastest->method.c_str(), *faust.fastest->faust_ratio, *faust.fastest->faust_ratio <= 0.5 ? "met" : "not met");
    } else {
        std::snprintf(line, sizeof line, "  at most half of Faust's cost per sample: not measured (%s)\n",
                      faust.problem.empty() ? "no measurement" : faust.problem.c_str());
    }
    print.text(line);
    const BenchMeasurement* large = nullptr;
    for (const auto& m : panels)
        if (m.masses >= 10000 && (!large || m.masses < large->masses)) large = &m;
    if (large) {
        std::snprintf(line, sizeof line,
                      "  a 10 000-mass membrane in real time at 48 kHz on one core: %s, %d masses, %.2f x realtime, "
                      "%.0f %% of a core (%s)\n",
                      large->method.c_str(), large->masses, large->realtime_factor(), large->core_percent(),
                      large->realtime_factor() >= 1.0 ? "met" : "not met");
    } else {
        std::snprintf(line, sizeof line, "  a 10 000-mass membrane in real time: not measured (no --sizes of 10000 or more)\n");
    }
    print.text(line);
}

}  // namespace

double max_relative_difference(const std::vector<double>& ours, const std::vector<double>& reference) {
    double peak = 0.0, worst = 0.0;
    for (std::size_t n = 0; n < reference.size(); ++n) {
        peak = std::max(peak, std::fabs(reference[n]));
        const double a = n < ours.size() ? ours[n] : NAN;
        worst = std::max(worst, std::isfinite(a) ? std::fabs(a - reference[n]) : INFINITY);
    }
    return peak > 0.0 ? worst / peak : worst;
}

int run_engine_bench(const BenchOptions& options, const CommandIo& io) {
    Printer print(options, io);
    const CpuPin pin;
    const int cpu = pin.cpu();
    print.text("ameoto bench engine: " + cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) +
               " CPUs" + (cpu >= 0 ? " (pinned to CPU " + std::to_string(cpu) + ")" : std::string()) +
               "; built with " AMEOTO_CXX_COMPILER " " AMEOTO_CXX_FLAGS "\n");
    char line[256];
    std::snprintf(line, sizeof line,
                  "Time: CPU time of this thread, median of %d runs after a warm-up, %.3g s per measurement. "
                  "ns/mass and ns/link\ndivide the step's time by masses x sub-steps and links x sub-steps; "
                  "%% core and x realtime are at 48 kHz.\n",
                  options.runs, options.seconds);
    print.text(line);
    const auto panels = bench_panels(options, print);
    const FaustResult faust = bench_triangle(options, print);
    summary(panels, faust, print);
    return exit_status::ok;
}

}  // namespace ameoto::client
