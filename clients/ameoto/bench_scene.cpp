// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_scene.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "engine/core/integrators/laned_network.hpp"
#include "engine/render/renderer.hpp"
#include "engine/render/umbrella_scene.hpp"

namespace ameoto::client {
namespace {

constexpr int block = 64;

struct Run {
    double cpu_s = 0.0;
    double drops = 0.0;
};

// CPU seconds and drops over `seconds` of audio after `warm_s`, for the umbrella scene at `rate`, its
// canopy in air (the default, canopy-air.md) or in vacuum (the seed's lattice, the model before).
Run run_umbrella(double rate, double full_level_db, double texture_margin_db, int max_full, double warm_s, double seconds, bool air = true) {
    RendererConfig c;
    c.air = air;
    c.sample_rate = bench_sample_rate;
    c.channels = 2;
    c.seed = 3;
    c.rain_rate_mm_per_h = rate;
    c.lod_full_level_db = full_level_db;
    c.lod_texture_margin_db = texture_margin_db;
    c.full_drops = max_full;
    Renderer r(c);
    std::vector<float> left(block), right(block);
    float* out[2] = {left.data(), right.data()};
    const long warm = static_cast<long>(warm_s * bench_sample_rate / block), timed = static_cast<long>(seconds * bench_sample_rate / block);
    for (long b = 0; b < warm; ++b) r.process(block, out);
    const double drops0 = static_cast<double>(r.stats().drops);
    const double start = thread_cpu_seconds();
    for (long b = 0; b < timed; ++b) r.process(block, out);
    return {thread_cpu_seconds() - start, static_cast<double>(r.stats().drops) - drops0};
}

// `ameoto render scene`'s work: the default umbrella scene as configure_for_scene makes it (seed 1,
// 4096-frame blocks, no adaptive LOD), at `rate` mm/h; CPU seconds per second of audio, over `seconds`
// of audio after the scene is built (its build, about 0.3 s, is not counted). `settle`: the lattice
// drops' settling (drop_on_canopy.hpp), or the model before it. `ceiling`: the widest vectors the laned
// canopy's kernels may use (laned_network.hpp): 32 (AVX2 where the CPU has it, the default) or 64 (the
// opt-in AVX-512 kernels, same bits: timed beside the default, as they may win on another CPU). `air`:
// the scene's umbrella in air (the built-in scene's, the default) or in vacuum (the model before). `push`:
// in air, the contacts' compressible push (air_push.hpp, the default) or the modes alone (the model before it).
double time_render(double rate, bool settle, double seconds, int ceiling = 32, bool air = true, bool push = true) {
    LanedNetwork::set_default_kernel_ceiling(ceiling);
    SceneDescription scene = *builtin_scene("umbrella");
    scene.surfaces[0].air = air;
    RendererConfig c = configure_for_scene(RendererConfig{}, scene);
    c.sample_rate = bench_sample_rate;
    c.channels = 2;
    c.seed = 1;
    c.rain_rate_mm_per_h = rate;
    c.settle = settle;
    c.air_push = push;
    Renderer r(c);
    constexpr int frames = 4096;
    std::vector<float> left(frames), right(frames);
    float* out[2] = {left.data(), right.data()};
    const long blocks = std::max(1L, static_cast<long>(seconds * bench_sample_rate / frames));
    const double start = thread_cpu_seconds();
    for (long b = 0; b < blocks; ++b) r.process(frames, out);
    const double cpu = thread_cpu_seconds() - start;
    LanedNetwork::set_default_kernel_ceiling(32);
    return cpu / (static_cast<double>(blocks * frames) / bench_sample_rate);
}

struct RenderRow {
    double rate = 0.0, target = 0.0;
    double per_s = 0.0, per_s_before = 0.0, dry_per_s = 0.0;   // CPU s per audio s: least of 3 rounds
    double per_s_avx512 = 0.0, dry_per_s_avx512 = 0.0;   // the same with the canopy's AVX-512 kernels
    double per_s_vacuum = 0.0, dry_per_s_vacuum = 0.0;   // the umbrella in vacuum (the model before air)
    double per_s_no_push = 0.0;                          // in air without the compressible push (the model before it)
};

// Three rounds of (settling, the model before it, the dry scene, the same in vacuum) back to back; the
// least of each (bench drop's estimator: docs/bench.md).
RenderRow render_row(double rate, double target, double seconds) {
    RenderRow row{rate, target, 1e300, 1e300, 1e300, 1e300, 1e300, 1e300, 1e300, 1e300};
    for (int i = 0; i < 3; ++i) {
        row.per_s = std::min(row.per_s, time_render(rate, true, seconds));
        row.per_s_before = std::min(row.per_s_before, time_render(rate, false, seconds));
        row.dry_per_s = std::min(row.dry_per_s, time_render(0.0, true, seconds));
        row.per_s_avx512 = std::min(row.per_s_avx512, time_render(rate, true, seconds, 64));
        row.dry_per_s_avx512 = std::min(row.dry_per_s_avx512, time_render(0.0, true, seconds, 64));
        row.per_s_vacuum = std::min(row.per_s_vacuum, time_render(rate, true, seconds, 32, false));
        row.dry_per_s_vacuum = std::min(row.dry_per_s_vacuum, time_render(0.0, true, seconds, 32, false));
        row.per_s_no_push = std::min(row.per_s_no_push, time_render(rate, true, seconds, 32, true, false));
    }
    return row;
}

struct Heavy {
    double drops_per_s = 0.0, mean = 0.0, p999 = 0.0, worst = 0.0;   // loads as fractions of the block period
    double full_drops = 0.0, priced_out = 0.0;
    // The governor's prior (lod_governor.hpp): each template size's worst block while the scene was built,
    // as fractions of a 64-, 256- and 1024-frame period.
    std::vector<double> prior_diameters_m, prior[3];
};
constexpr int prior_frames[3] = {64, 256, 1024};

// Heavy rain: the umbrella (in air or in vacuum) and a pond at 50 mm/h, 64-frame blocks, the governor on
// measured load, `seconds` of audio timed after a 1 s ramp-in.
Heavy heavy_rain(bool air, double seconds, bool push = true) {
    SceneDescription scene = heavy_rain_bench_scene();
    scene.surfaces[0].air = air;
    RendererConfig base;
    base.air_push = push;
    base.sample_rate = bench_sample_rate;
    base.channels = 2;
    base.seed = 5;
    base.adaptive_lod = true;
    Renderer heavy(configure_for_scene(base, scene));
    std::vector<float> left(block), right(block);
    float* out[2] = {left.data(), right.data()};
    const double period = block / bench_sample_rate;
    // The rain ramps in for 1 s, timed and told to the governor as ameotod's audio thread does from its
    // first callback (the governor learns the lattice drops' price from it), but not counted.
    for (int b = 0; b < static_cast<int>(1.0 / period); ++b) {
        const double start = thread_cpu_seconds();
        heavy.process(block, out);
        heavy.set_measured_load((thread_cpu_seconds() - start) / period);
    }
    std::vector<double> loads;
    const std::uint64_t drops0 = heavy.stats().drops + heavy.stats().surface_drops;
    const std::uint64_t full0 = heavy.stats().rain_tiers.full, priced0 = heavy.stats().rain_tiers.priced_out;
    const long blocks = static_cast<long>(seconds / period);
    for (long b = 0; b < blocks; ++b) {
        const double start = thread_cpu_seconds();
        heavy.process(block, out);
        const double load = (thread_cpu_seconds() - start) / period;
        heavy.set_measured_load(load);
        loads.push_back(load);
    }
    Heavy h;
    h.drops_per_s = static_cast<double>(heavy.stats().drops + heavy.stats().surface_drops - drops0) / seconds;
    for (double l : loads) h.mean += l;
    h.mean /= static_cast<double>(loads.size());
    std::sort(loads.begin(), loads.end());
    h.p999 = loads[std::min(loads.size() - 1, static_cast<std::size_t>(0.999 * static_cast<double>(loads.size())))];
    h.worst = loads.back();
    // What the governor let through: lattice drops admitted, and those its price turned into templates.
    h.full_drops = static_cast<double>(heavy.stats().rain_tiers.full - full0);
    h.priced_out = static_cast<double>(heavy.stats().rain_tiers.priced_out - priced0);
    const ImpactTemplateTable& t = heavy.umbrella().templates;
    h.prior_diameters_m = t.diameters_m;
    for (int f = 0; f < 3; ++f)
        for (int k = 0; k < static_cast<int>(t.diameters_m.size()); ++k)
            h.prior[f].push_back(t.worst_cpu_s(prior_frames[f], k) / (prior_frames[f] / bench_sample_rate));
    return h;
}

}  // namespace

SceneDescription heavy_rain_bench_scene() {
    SceneDescription scene = *builtin_scene("umbrella");
    scene.rain.rate_mm_per_h = 50.0;
    SurfaceDescription pond;
    pond.name = "pond";
    pond.kind = SurfaceKind::water;
    pond.material = "pond";
    pond.size_x_m = 4.0;
    pond.size_y_m = 3.0;
    pond.x_m = 3.0;
    scene.surfaces.push_back(pond);
    return scene;
}

int run_scene_bench(const BenchOptions& options, const CommandIo& io) {
    const double seconds = std::clamp(options.seconds * 4.0, 1.0, 20.0);   // audio seconds per measurement
    io.err << "ameoto bench scene: the dry umbrella, then each tier forced, then heavy rain with a pond ("
           << seconds << " s of audio each)...\n";
    // Each tier against the dry scene measured right before it (the machine's load drifts), median of 3.
    auto median3 = [](double a, double b, double c) { return std::max(std::min(a, b), std::min(std::max(a, b), c)); };
    const Run dry = run_umbrella(0.0, 6.0, 20.0, 4, 0.2, seconds);
    const double dry_share = dry.cpu_s / seconds;
    const double dry_share_vacuum = run_umbrella(0.0, 6.0, 20.0, 4, 0.2, seconds, false).cpu_s / seconds;
    struct Tier {
        const char* name;
        double rate, full_db, margin_db;
        int max_full;
        Run run;
        double ns_per_drop = 0.0, drops_per_s_on_a_core = 0.0;
    };
    std::vector<Tier> tiers = {{"full", 0.3, -1000.0, 20.0, 64, {}},
                               {"template", 200.0, 1000.0, 1000.0, 0, {}},
                               {"texture", 200.0, 1000.0, -1000.0, 0, {}}};
    for (Tier& t : tiers) {
        double extra[3];
        for (double& e : extra) {
            const Run base = run_umbrella(0.0, 6.0, 20.0, 4, 0.2, seconds / 2);
            t.run = run_umbrella(t.rate, t.full_db, t.margin_db, t.max_full, 1.0, seconds / 2);
            e = t.run.cpu_s - base.cpu_s;
        }
        t.run.cpu_s = median3(extra[0], extra[1], extra[2]) + dry.cpu_s / 2;
        t.run.drops *= 2.0;   // per `seconds`, as the dry run
        t.run.cpu_s *= 2.0;
        // A cost under the noise of the machine (the dry scene measured again) is reported as none (0).
        const double per_drop = std::max(t.run.cpu_s - dry.cpu_s, 0.0) / std::max(t.run.drops, 1.0);
        t.ns_per_drop = per_drop * 1e9;
        t.drops_per_s_on_a_core = per_drop > 0.0 ? (1.0 - dry_share) / per_drop : 0.0;
    }

    const Heavy heavy = heavy_rain(true, seconds);
    const Heavy heavy_vacuum = heavy_rain(false, seconds);
    const Heavy heavy_no_push = heavy_rain(true, seconds, false);

    // Offline renders (ameoto render scene's work): the default scene at its own rate, and heavy rain.
    const RenderRow renders[] = {render_row(builtin_scene("umbrella")->rain.rate_mm_per_h, 20.0, seconds),
                                 render_row(50.0, 4.0, seconds)};

    if (options.json) {
        for (const RenderRow& r : renders)
            io.out << "{\"suite\":\"scene\",\"measurement\":\"render\",\"rain_mm_per_h\":" << json_number(r.rate)
                   << ",\"realtime_factor\":" << json_number(1.0 / r.per_s) << ",\"realtime_factor_before\":"
                   << json_number(1.0 / r.per_s_before) << ",\"speedup\":" << json_number(r.per_s_before / r.per_s)
                   << ",\"dry_share\":" << json_number(r.dry_per_s / r.per_s) << ",\"target\":" << json_number(r.target)
                   << ",\"realtime_factor_avx512\":" << json_number(1.0 / r.per_s_avx512) << ",\"dry_percent_core\":"
                   << json_number(100.0 * r.dry_per_s) << ",\"dry_percent_core_avx512\":" << json_number(100.0 * r.dry_per_s_avx512)
                   << ",\"realtime_factor_vacuum\":" << json_number(1.0 / r.per_s_vacuum) << ",\"dry_percent_core_vacuum\":"
                   << json_number(100.0 * r.dry_per_s_vacuum) << ",\"realtime_factor_no_push\":" << json_number(1.0 / r.per_s_no_push) << "}\n";
        io.out << "{\"suite\":\"scene\",\"measurement\":\"dry umbrella\",\"percent_core\":" << json_number(100.0 * dry_share)
               << ",\"percent_core_vacuum\":" << json_number(100.0 * dry_share_vacuum) << "}\n";
        for (const Tier& t : tiers)
            io.out << "{\"suite\":\"scene\",\"measurement\":\"tier\",\"tier\":" << json_string(t.name) << ",\"rain_mm_per_h\":"
                   << json_number(t.rate) << ",\"drops_per_s\":" << json_number(t.run.drops / seconds)
                   << ",\"ns_per_drop\":" << json_number(t.ns_per_drop) << ",\"drops_per_s_on_a_core\":"
                   << json_number(t.drops_per_s_on_a_core) << "}\n";
        io.out << "{\"suite\":\"scene\",\"measurement\":\"heavy rain\",\"rain_mm_per_h\":50,\"drops_per_s\":"
               << json_number(heavy.drops_per_s) << ",\"block_frames\":64,\"mean_percent\":" << json_number(100.0 * heavy.mean)
               << ",\"p999_percent\":" << json_number(100.0 * heavy.p999) << ",\"max_percent\":" << json_number(100.0 * heavy.worst)
               << ",\"full_drops\":" << json_number(heavy.full_drops) << ",\"priced_out\":" << json_number(heavy.priced_out)
               << ",\"target_mean_percent\":25,\"target_p999_percent\":60,\"mean_percent_vacuum\":"
               << json_number(100.0 * heavy_vacuum.mean) << ",\"p999_percent_vacuum\":" << json_number(100.0 * heavy_vacuum.p999)
               << ",\"max_percent_vacuum\":" << json_number(100.0 * heavy_vacuum.worst) << ",\"mean_percent_no_push\":"
               << json_number(100.0 * heavy_no_push.mean) << ",\"p999_percent_no_push\":" << json_number(100.0 * heavy_no_push.p999) << "}\n";
        io.out << "{\"suite\":\"scene\",\"measurement\":\"lattice prior\",\"diameters_mm\":[";
        for (std::size_t k = 0; k < heavy.prior_diameters_m.size(); ++k) io.out << (k ? "," : "") << json_number(1e3 * heavy.prior_diameters_m[k]);
        io.out << "]";
        for (int f = 0; f < 3; ++f) {
            io.out << ",\"percent_" << prior_frames[f] << "\":[";
            for (std::size_t k = 0; k < heavy.prior[f].size(); ++k) io.out << (k ? "," : "") << json_number(100.0 * heavy.prior[f][k]);
            io.out << "]";
        }
        io.out << "}\n";
        return exit_status::ok;
    }
    char line[400];
    std::snprintf(line, sizeof line,
                  "umbrella scene, 48 kHz stereo; the dry scene (canopy in air, far field) takes %.1f %% of a core; in vacuum (the "
                  "model before) %.1f %%: %.2f x its cost\n",
                  100.0 * dry_share, 100.0 * dry_share_vacuum, dry_share / dry_share_vacuum);
    io.out << line;
    std::snprintf(line, sizeof line, "%-10s %10s %12s %14s %22s\n", "tier", "mm/h", "drops/s", "CPU ns/drop", "drops/s on one core");
    io.out << line;
    for (const Tier& t : tiers) {
        if (t.drops_per_s_on_a_core > 0.0) {
            std::snprintf(line, sizeof line, "%-10s %10.1f %12.0f %14.0f %22.0f\n", t.name, t.rate, t.run.drops / seconds, t.ns_per_drop,
                          t.drops_per_s_on_a_core);
        } else {
            std::snprintf(line, sizeof line, "%-10s %10.1f %12.0f %14s %22s\n", t.name, t.rate, t.run.drops / seconds,
                          "below noise", "(unbounded here)");
        }
        io.out << line;
    }
    std::snprintf(line, sizeof line,
                  "heavy rain: 50 mm/h on the umbrella and a 4 x 3 m pond, %.0f drops/s, 64-frame blocks:\n"
                  "  mean callback %.1f %% of the block period (target 25 %%: %s), 99.9th percentile %.1f %% (target 60 %%: %s)\n",
                  heavy.drops_per_s, 100.0 * heavy.mean, heavy.mean <= 0.25 ? "met" : "not met", 100.0 * heavy.p999, heavy.p999 <= 0.60 ? "met" : "not met");
    io.out << line;
    std::snprintf(line, sizeof line, "  worst block %.1f %%; lattice drops admitted %.0f, priced out by the governor %.0f\n", 100.0 * heavy.worst,
                  heavy.full_drops, heavy.priced_out);
    io.out << line;
    std::snprintf(line, sizeof line,
                  "  the umbrella in vacuum (the model before air), same rain: mean %.1f %%, 99.9th percentile %.1f %%, worst %.1f %%; "
                  "lattice drops admitted %.0f, priced out %.0f\n",
                  100.0 * heavy_vacuum.mean, 100.0 * heavy_vacuum.p999, 100.0 * heavy_vacuum.worst, heavy_vacuum.full_drops,
                  heavy_vacuum.priced_out);
    io.out << line;
    std::snprintf(line, sizeof line,
                  "  in air without the compressible push (the model before it), same rain: mean %.1f %%, 99.9th percentile %.1f %%\n",
                  100.0 * heavy_no_push.mean, 100.0 * heavy_no_push.p999);
    io.out << line;
    io.out << "  the governor's prior (each template size's worst block while the scene was built, % of a 64 / 256 / 1024-frame\n"
              "  period; a rain drop gets a lattice only where its size's figure and the load now fit under 50 %):\n   ";
    const std::size_t sizes = heavy.prior_diameters_m.size();
    for (std::size_t k = 0; k < sizes; ++k) {
        if (k % 4 != 0 && k + 1 != sizes) continue;   // every fourth size (5 % apart) and the largest
        std::snprintf(line, sizeof line, " %.2f mm %.0f/%.0f/%.0f%s", 1e3 * heavy.prior_diameters_m[k], 100.0 * heavy.prior[0][k],
                      100.0 * heavy.prior[1][k], 100.0 * heavy.prior[2][k], k + 1 == sizes ? "\n" : (k % 16 == 12 ? ";\n   " : ";"));
        io.out << line;
    }
    io.out << "offline render (ameoto render scene's work: the default umbrella scene, its canopy in air, seed 1, 4096-frame\n"
              "blocks, its build not counted; least of 3 rounds of: with settling, the model before it, the dry scene, the same\n"
              "in vacuum, in air without the compressible push):\n";
    for (const RenderRow& r : renders) {
        std::snprintf(line, sizeof line,
                      "  %4.0f mm/h: %.1f x real time (target %.0f: %s); before settling %.1f x, so %.2f x faster; the dry "
                      "scene (canopy, far field, texture bed) is %.0f %% of it\n",
                      r.rate, 1.0 / r.per_s, r.target, 1.0 / r.per_s >= r.target ? "met" : "not met", 1.0 / r.per_s_before,
                      r.per_s_before / r.per_s, 100.0 * r.dry_per_s / r.per_s);
        io.out << line;
        std::snprintf(line, sizeof line,
                      "             the canopy's opt-in AVX-512 kernels (same bits), same rounds: %.1f x (%.2f of the default's "
                      "time); the dry scene %.1f %% of a core (AVX-512 %.1f %%)\n",
                      1.0 / r.per_s_avx512, r.per_s_avx512 / r.per_s, 100.0 * r.dry_per_s, 100.0 * r.dry_per_s_avx512);
        io.out << line;
        std::snprintf(line, sizeof line,
                      "             the umbrella in vacuum (the model before air), same rounds: %.1f x real time (air is %.2f x "
                      "faster); its dry scene %.1f %% of a core\n",
                      1.0 / r.per_s_vacuum, r.per_s_vacuum / r.per_s, 100.0 * r.dry_per_s_vacuum);
        io.out << line;
        std::snprintf(line, sizeof line,
                      "             in air without the compressible push (the model before it), same rounds: %.1f x real time (the "
                      "push costs %.2f x)\n",
                      1.0 / r.per_s_no_push, r.per_s / r.per_s_no_push);
        io.out << line;
    }
    return exit_status::ok;
}

}  // namespace ameoto::client
