// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_drop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "engine/core/integrators/laned_network.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/drop_on_canopy.hpp"

namespace ameoto::client {
namespace {

constexpr double window_s = 0.1;   // from placement through impact and breakup

// The scene: 5 mm drops on the canopy in vacuum (the seed's lattice under the baffled Rayleigh sum, the
// engine's own default), or in air (the built-in scenes' umbrella: its air-loaded modes heard as dipoles
// with the compressible push, docs/canopy-air.md).
DropOnCanopyConfig drop_config(bool settle, bool air) {
    DropOnCanopyConfig config;
    config.settle = settle;
    config.sample_rate = bench_sample_rate;
    config.capacity = 8;
    config.max_diameter = 5.2e-3;   // only 5 mm lattices: builds in well under a second
    config.air = air;
    return config;
}

// CPU seconds to render window_s of a fresh scene holding `drops` 5 mm drops; `settle`: the model
// (true, the default) or the model before settling (every mass stepped until its drop retires).
// `ceiling`: the widest vectors of the laned canopy's kernels (laned_network.hpp): 32, AVX2 where the CPU
// has it (the default), or 64, the opt-in AVX-512 kernels (the same bits), timed beside it. `in_air`: the
// canopy in air, never stepped, each scene built on a copy of it (its modes take 0.4 s to build).
double time_window(int drops, bool settle = true, int ceiling = 32, const Canopy* in_air = nullptr) {
    LanedNetwork::set_default_kernel_ceiling(ceiling);
    const DropOnCanopyConfig config = drop_config(settle, in_air != nullptr);
    std::optional<DropOnCanopy> built;
    DropOnCanopy& scene = in_air ? built.emplace(config, *in_air) : built.emplace(config);
    for (int d = 0; d < drops; ++d) {
        const double azimuth = 2.0 * constants::pi * d / 8.0;   // one drop per panel
        scene.drop(5e-3, 0.0, 0.25 * std::cos(azimuth), 0.25 * std::sin(azimuth));
    }
    std::vector<float> out(64);
    float* outputs[1] = {out.data()};
    const int blocks = static_cast<int>(window_s * bench_sample_rate / 64);
    const double start = thread_cpu_seconds();
    for (int b = 0; b < blocks; ++b) scene.process(64, outputs);
    const double cpu = thread_cpu_seconds() - start;
    LanedNetwork::set_default_kernel_ceiling(32);
    return cpu;
}

// The three scenes timed in rounds, one of each back to back, so that a round's three figures see the
// same machine (the 2-CPU VM's speed moves by half within minutes: docs/bench.md), and the per-drop
// difference is not taken between runs minutes apart.
struct Rounds {
    std::vector<double> base, one, eight;   // CPU s per window, one entry per round
    std::vector<double> one_before, eight_before;   // the same without settling (the model before it)
    std::vector<double> base_avx512, eight_avx512;      // the canopy's opt-in AVX-512 kernels
    std::vector<double> base_air, eight_air;            // the canopy in air
};

Rounds time_rounds(int runs, const Canopy& in_air) {
    Rounds r;
    for (int i = 0; i < runs; ++i) {
        r.base.push_back(time_window(0));
        r.one.push_back(time_window(1));
        r.eight.push_back(time_window(8));
        r.one_before.push_back(time_window(1, false));
        r.eight_before.push_back(time_window(8, false));
        r.base_avx512.push_back(time_window(0, true, 64));
        r.eight_avx512.push_back(time_window(8, true, 64));
        r.base_air.push_back(time_window(0, true, 32, &in_air));
        r.eight_air.push_back(time_window(8, true, 32, &in_air));
    }
    return r;
}

double least(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

// Drops at once from s per sample: (period - baseline) / per drop (8-drop figure).
double drops_at_once(double base, double eight) {
    const double per_drop = std::max((eight - base) / 8.0, 1e-12);
    return (1.0 / bench_sample_rate - base) / per_drop;
}

}  // namespace

int run_drop_bench(const BenchOptions& options, const CommandIo& io) {
    const int runs = options.runs;
    const double samples = window_s * bench_sample_rate;
    io.err << "ameoto bench drop: timing the canopy alone, 1 and 8 drops (" << runs << " rounds)...\n";
    (void)time_window(1);   // warm-up: lattice caches, page faults
    const Canopy in_air = DropOnCanopy::fresh_canopy(drop_config(true, true));
    const Rounds r = time_rounds(runs, in_air);
    // Two estimators of each scene's cost per sample. The least of the runs: the code's cost, since
    // whatever else the machine does can only lengthen a run of deterministic work (the estimator of
    // Chen & Revels, "Robust benchmarking in noisy environments", 2016). The median: what this machine
    // gave now, its neighbours included.
    const double base = least(r.base) / samples, one = least(r.one) / samples, eight = least(r.eight) / samples;
    const double base_med = median(r.base) / samples, one_med = median(r.one) / samples, eight_med = median(r.eight) / samples;
    const double period = 1.0 / bench_sample_rate;
    const double at_once = drops_at_once(base, eight);
    const double at_once_median = drops_at_once(base_med, eight_med);
    // The model before settling, timed in the same rounds against the same baseline.
    const double one_before = least(r.one_before) / samples, eight_before = least(r.eight_before) / samples;
    const double eight_before_med = median(r.eight_before) / samples;
    const double at_once_before = drops_at_once(base, eight_before);
    const double at_once_before_median = drops_at_once(base_med, eight_before_med);
    const double speedup = std::max(eight_before - base, 1e-12) / std::max(eight - base, 1e-12);
    // The canopy's AVX-512 kernels, same rounds: its own baseline and 8 drops.
    const double base_avx512 = least(r.base_avx512) / samples, eight_avx512 = least(r.eight_avx512) / samples;
    const double at_once_avx512 = drops_at_once(base_avx512, eight_avx512);
    // The canopy in air, same rounds: its own baseline and 8 drops.
    const double base_air = least(r.base_air) / samples, eight_air = least(r.eight_air) / samples;
    const double at_once_air = drops_at_once(base_air, eight_air);
    const double per_drop_air_ns = std::max((eight_air - base_air) / 8.0, 1e-12) * 1e9;
    double round_low = 1e300, round_high = -1e300;   // each round's own figure
    for (int i = 0; i < runs; ++i) {
        const double a = drops_at_once(r.base[static_cast<std::size_t>(i)] / samples, r.eight[static_cast<std::size_t>(i)] / samples);
        round_low = std::min(round_low, a);
        round_high = std::max(round_high, a);
    }

    struct Row {
        const char* what;
        int drops;
        double ns_per_sample, ns_median;   // least of the runs, median
        double ns_before;                  // least of the runs, the model before settling
    };
    const Row rows[] = {{"canopy (no drop)", 0, base * 1e9, base_med * 1e9, base * 1e9},
                        {"1 drop", 1, one * 1e9, one_med * 1e9, one_before * 1e9},
                        {"8 drops", 8, eight * 1e9, eight_med * 1e9, eight_before * 1e9}};
    auto per_drop_ns = [&](const Row& row, bool use_median) {
        const double with = use_median ? row.ns_median : row.ns_per_sample, without = use_median ? rows[0].ns_median : rows[0].ns_per_sample;
        return std::max((with - without) / row.drops, 1e-3);
    };
    auto per_drop_before_ns = [&](const Row& row) { return std::max((row.ns_before - rows[0].ns_per_sample) / row.drops, 1e-3); };
    if (options.json) {
        for (const Row& row : rows) {
            io.out << "{\"suite\":\"drop\",\"measurement\":" << json_string(row.what) << ",\"drops\":" << row.drops
                   << ",\"diameter_mm\":5,\"sample_rate_hz\":48000,\"ns_per_sample\":" << json_number(row.ns_per_sample)
                   << ",\"ns_per_sample_median\":" << json_number(row.ns_median)
                   << ",\"ns_per_drop_per_sample\":" << (row.drops ? json_number(per_drop_ns(row, false)) : std::string("null"))
                   << ",\"ns_per_drop_per_sample_median\":" << (row.drops ? json_number(per_drop_ns(row, true)) : std::string("null"))
                   << ",\"percent_core\":" << json_number(100.0 * row.ns_per_sample * 1e-9 / period)
                   << ",\"ns_per_sample_before\":" << json_number(row.ns_before)
                   << ",\"ns_per_drop_per_sample_before\":" << (row.drops ? json_number(per_drop_before_ns(row)) : std::string("null"))
                   << "}\n";
        }
        io.out << "{\"suite\":\"drop\",\"measurement\":\"drops at once in real time\",\"drops\":" << json_number(at_once)
               << ",\"drops_median\":" << json_number(at_once_median) << ",\"drops_round_low\":" << json_number(round_low)
               << ",\"drops_round_high\":" << json_number(round_high) << ",\"runs\":" << runs << ",\"target\":16,\"drops_before\":" << json_number(at_once_before)
               << ",\"drops_before_median\":" << json_number(at_once_before_median) << ",\"speedup\":" << json_number(speedup)
               << ",\"drops_avx512\":" << json_number(at_once_avx512) << ",\"canopy_ns_per_sample_avx512\":" << json_number(base_avx512 * 1e9)
               << ",\"drops_air\":" << json_number(at_once_air) << ",\"canopy_ns_per_sample_air\":" << json_number(base_air * 1e9)
               << ",\"ns_per_drop_per_sample_air\":" << json_number(per_drop_air_ns) << "}\n";
        return exit_status::ok;
    }
    char line[400];
    io.out << "5 mm water drops at terminal speed on the 8-panel nylon canopy, 48 kHz, far-field sound;\n"
              "thread CPU time over the first 0.1 s (impact and breakup), "
           << runs << " rounds of the three scenes back to back: the least of the runs (the code's cost) and their median\n";
    std::snprintf(line, sizeof line, "%-20s %6s %11s %16s %8s %11s %16s\n", "scene", "drops", "ns/sample", "ns/drop/sample",
                  "% core", "median ns", "median per drop");
    io.out << line;
    for (const Row& row : rows) {
        std::snprintf(line, sizeof line, "%-20s %6d %11.0f %16s %8.1f %11.0f %16s\n", row.what, row.drops, row.ns_per_sample,
                      row.drops ? std::to_string(std::lround(per_drop_ns(row, false))).c_str() : "-",
                      100.0 * row.ns_per_sample * 1e-9 / period, row.ns_median,
                      row.drops ? std::to_string(std::lround(per_drop_ns(row, true))).c_str() : "-");
        io.out << line;
    }
    std::snprintf(line, sizeof line, "drops at once in real time on one core: %.1f (target 16: %s)\n", at_once,
                  at_once >= 16.0 ? "met" : "not met");
    io.out << line;
    std::snprintf(line, sizeof line, "  from the medians: %.1f; each round on its own: %.1f to %.1f\n", at_once_median,
                  round_low, round_high);
    io.out << line;
    std::snprintf(line, sizeof line,
                  "the model before settling (resting and departed liquid stepped every sample), same rounds: %.0f ns per drop "
                  "per sample, %.1f drops at once (medians %.1f); settling makes a drop %.2f times cheaper\n",
                  per_drop_before_ns(rows[2]), at_once_before, at_once_before_median, speedup);
    io.out << line;
    std::snprintf(line, sizeof line,
                  "the canopy's opt-in AVX-512 kernels (same bits), same rounds: canopy %.0f ns per sample against %.0f, "
                  "%.1f drops at once\n",
                  base_avx512 * 1e9, base * 1e9, at_once_avx512);
    io.out << line;
    std::snprintf(line, sizeof line,
                  "the canopy in air (the built-in scenes' umbrella: its modes heard as dipoles, with the push), same rounds: "
                  "canopy %.0f ns per sample, %.0f ns per drop per sample, %.1f drops at once (target 16: %s)\n",
                  base_air * 1e9, per_drop_air_ns, at_once_air, at_once_air >= 16.0 ? "met" : "not met");
    io.out << line;
    io.out << "limit: each drop's per-mass passes over its 122 masses (drag's square root, update) and its sparse link "
              "pass, every sample until the splash is in the air, then steps of 3-4 samples (coarse steps; choosing them "
              "costs a look over its links every 20 or so samples); then the canopy (its panels already SIMD lanes) and "
              "its far field; see docs/bench.md, \"ameoto bench drop\"\n";
    return exit_status::ok;
}

}  // namespace ameoto::client
