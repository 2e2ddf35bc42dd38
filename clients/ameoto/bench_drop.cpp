#include "clients/ameoto/bench_drop.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/drop_on_canopy.hpp"

namespace ameoto::client {
namespace {

constexpr double window_s = 0.1;   // from placement through impact and breakup

// CPU seconds to render window_s of a fresh scene holding `drops` 5 mm drops.
double time_window(int drops) {
    DropOnCanopyConfig config;
    config.sample_rate = bench_sample_rate;
    config.capacity = 8;
    config.max_diameter = 5.2e-3;   // only 5 mm lattices: builds in well under a second
    DropOnCanopy scene(config);
    for (int d = 0; d < drops; ++d) {
        const double azimuth = 2.0 * constants::pi * d / 8.0;   // one drop per panel
        scene.drop(5e-3, 0.0, 0.25 * std::cos(azimuth), 0.25 * std::sin(azimuth));
    }
    std::vector<float> out(64);
    float* outputs[1] = {out.data()};
    const int blocks = static_cast<int>(window_s * bench_sample_rate / 64);
    const double start = thread_cpu_seconds();
    for (int b = 0; b < blocks; ++b) scene.process(64, outputs);
    return thread_cpu_seconds() - start;
}

double median_window(int drops, int runs) {
    std::vector<double> t;
    for (int r = 0; r < runs; ++r) t.push_back(time_window(drops));
    return median(t);
}

}  // namespace

int run_drop_bench(const BenchOptions& options, const CommandIo& io) {
    const int runs = options.runs;
    const double samples = window_s * bench_sample_rate;
    io.err << "ameoto bench drop: timing the canopy alone, 1 and 8 drops (" << runs << " runs each)...\n";
    (void)time_window(1);   // warm-up: lattice caches, page faults
    const double base = median_window(0, runs) / samples;
    const double one = median_window(1, runs) / samples;
    const double eight = median_window(8, runs) / samples;
    const double period = 1.0 / bench_sample_rate;
    const double per_drop_1 = std::max(one - base, 1e-12);
    const double per_drop_8 = std::max((eight - base) / 8.0, 1e-12);
    const double at_once = (period - base) / per_drop_8;

    struct Row {
        const char* what;
        int drops;
        double ns_per_sample;
        double per_drop_ns;
    };
    const Row rows[] = {{"canopy (no drop)", 0, base * 1e9, 0.0}, {"1 drop", 1, one * 1e9, per_drop_1 * 1e9},
                        {"8 drops", 8, eight * 1e9, per_drop_8 * 1e9}};
    if (options.json) {
        for (const Row& r : rows) {
            io.out << "{\"suite\":\"drop\",\"measurement\":" << json_string(r.what) << ",\"drops\":" << r.drops
                   << ",\"diameter_mm\":5,\"sample_rate_hz\":48000,\"ns_per_sample\":" << json_number(r.ns_per_sample)
                   << ",\"ns_per_drop_per_sample\":" << (r.drops ? json_number(r.per_drop_ns) : std::string("null"))
                   << ",\"percent_core\":" << json_number(100.0 * r.ns_per_sample * 1e-9 / period) << "}\n";
        }
        io.out << "{\"suite\":\"drop\",\"measurement\":\"drops at once in real time\",\"drops\":" << json_number(at_once)
               << ",\"target\":16}\n";
        return exit_status::ok;
    }
    char line[160];
    io.out << "5 mm water drops at terminal speed on the 8-panel nylon canopy, 48 kHz, far-field sound;\n"
              "thread CPU time over the first 0.1 s (impact and breakup), median of "
           << runs << " runs\n";
    std::snprintf(line, sizeof line, "%-20s %8s %14s %16s %8s\n", "scene", "drops", "ns/sample", "ns/drop/sample", "% core");
    io.out << line;
    for (const Row& r : rows) {
        std::snprintf(line, sizeof line, "%-20s %8d %14.0f %16s %8.1f\n", r.what, r.drops, r.ns_per_sample,
                      r.drops ? std::to_string(static_cast<long>(r.per_drop_ns)).c_str() : "-", 100.0 * r.ns_per_sample * 1e-9 / period);
        io.out << line;
    }
    std::snprintf(line, sizeof line, "drops at once in real time on one core: %.1f (target 16: %s)\n", at_once,
                  at_once >= 16.0 ? "met" : "not met");
    io.out << line;
    io.out << "limit: each drop's per-mass passes (drag's square root, update: all 122 masses every step, most of them "
              "single-mass pieces in flight) and its sparse link pass; then the canopy (its panels already stepped as SIMD "
              "lanes) and its far field; see docs/bench.md, \"ameoto bench drop\"\n";
    return exit_status::ok;
}

}  // namespace ameoto::client
