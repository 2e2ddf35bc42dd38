// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_formats.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "clients/ameoto/bench_scene.hpp"
#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto::client {
namespace {

constexpr int format_block = 256;
constexpr int format_rounds = 3;

// CPU seconds per sample over `seconds` of audio, after 0.5 s of the rain ramping in (not counted).
double format_seconds_per_sample(const OutputFormat& format, double seconds) {
    RendererConfig base;
    base.sample_rate = bench_sample_rate;
    base.seed = 5;
    base.adaptive_lod = false;   // the same drops in every format: only the output's cost differs
    apply_output_format(base, format);
    Renderer r(configure_for_scene(base, heavy_rain_bench_scene()));
    // configure_for_scene keeps the format's channels and listener (they are not the scene's).
    std::vector<std::vector<float>> planes(static_cast<std::size_t>(format.channels), std::vector<float>(format_block));
    std::vector<float*> out;
    for (auto& p : planes) out.push_back(p.data());
    for (int b = 0; b < static_cast<int>(0.5 * bench_sample_rate / format_block); ++b) r.process(format_block, out.data());
    const long blocks = std::max(1L, static_cast<long>(seconds * bench_sample_rate / format_block));
    const double start = thread_cpu_seconds();
    for (long b = 0; b < blocks; ++b) r.process(format_block, out.data());
    return (thread_cpu_seconds() - start) / static_cast<double>(blocks * format_block);
}

}  // namespace

int run_formats_bench(const BenchOptions& options, const CommandIo& io) {
    const double seconds = std::clamp(options.seconds * 4.0, 0.5, 40.0);
    std::vector<OutputFormat> formats;
    std::string error;
    for (const char* name : {"stereo", "ambix:1", "ambix:2", "ambix:3"}) formats.push_back(*parse_output_format(name, error));
    std::vector<double> best(formats.size(), 1e300);
    io.err << "ameoto bench formats: heavy rain (50 mm/h, umbrella and pond), " << format_block << "-frame blocks, "
           << format_rounds << " format_rounds of " << seconds << " s per format...\n";
    for (int round = 0; round < format_rounds; ++round)
        for (std::size_t f = 0; f < formats.size(); ++f) best[f] = std::min(best[f], format_seconds_per_sample(formats[f], seconds));
    const double stereo = best[0];
    for (std::size_t f = 0; f < formats.size(); ++f) {
        const double ns = best[f] * 1e9, core = 100.0 * best[f] * bench_sample_rate, ratio = best[f] / stereo;
        const double extra = 100.0 * (best[f] - stereo) * bench_sample_rate;
        if (options.json) {
            io.out << "{\"suite\":\"formats\",\"format\":\"" << formats[f].name() << "\",\"channels\":" << formats[f].channels
                   << ",\"block_frames\":" << format_block << ",\"ns_per_sample\":" << json_number(ns) << ",\"core_percent\":"
                   << json_number(core) << ",\"ratio_to_stereo\":" << json_number(ratio) << ",\"extra_core_percent\":"
                   << json_number(extra) << "}\n";
        } else {
            char line[200];
            std::snprintf(line, sizeof line, "%-8s %2d channels: %8.0f ns/sample, %5.1f %% of a core at 48 kHz, %.3f x stereo (%+.2f %% of a core)\n",
                          formats[f].name().c_str(), formats[f].channels, ns, core, ratio, extra);
            io.out << line;
        }
    }
    return exit_status::ok;
}

}  // namespace ameoto::client
