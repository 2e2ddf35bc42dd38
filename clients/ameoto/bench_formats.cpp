// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_formats.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "clients/ameoto/bench_scene.hpp"
#include "clients/ameoto/bench_timer.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "engine/render/binaural_decoder.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto::client {
namespace {

constexpr int format_block = 256;
constexpr int format_rounds = 3;

// CPU seconds per sample over `seconds` of audio, after 0.5 s of the rain ramping in (not counted).
// Binaural: the renderer's third-order bus and the decoder to two ears (built before, not counted), as
// ameotod's audio thread runs them (server/realtime/binaural_stage.hpp).
double format_seconds_per_sample(const OutputFormat& format, double seconds, std::string& error) {
    RendererConfig base;
    base.sample_rate = bench_sample_rate;
    base.seed = 5;
    base.adaptive_lod = false;   // the same drops in every format: only the output's cost differs
    apply_output_format(base, format);
    Renderer r(configure_for_scene(base, heavy_rain_bench_scene()));
    // configure_for_scene keeps the format's channels and listener (they are not the scene's).
    const int bus = r.config().channels;   // binaural: 16, decoded to 2
    std::vector<std::vector<float>> planes(static_cast<std::size_t>(bus), std::vector<float>(format_block));
    std::vector<float*> out;
    for (auto& p : planes) out.push_back(p.data());
    std::unique_ptr<BinauralDecoder> decoder;
    if (format.kind == OutputKind::binaural) {
        auto made = BinauralDecoder::create(BinauralDecoder::default_sofa_path, format.order, bench_sample_rate, format_block);
        if (!made.decoder) {
            error = made.error;
            return -1.0;
        }
        decoder = std::move(made.decoder);
    }
    std::vector<float> left(format_block), right(format_block);
    auto block = [&] {
        r.process(format_block, out.data());
        if (decoder) decoder->process(out.data(), format_block, left.data(), right.data());
    };
    for (int b = 0; b < static_cast<int>(0.5 * bench_sample_rate / format_block); ++b) block();
    const long blocks = std::max(1L, static_cast<long>(seconds * bench_sample_rate / format_block));
    const double start = thread_cpu_seconds();
    for (long b = 0; b < blocks; ++b) block();
    return (thread_cpu_seconds() - start) / static_cast<double>(blocks * format_block);
}

// The decoder alone, on a bus of uniform noise (its cost does not depend on the signal): CPU seconds per
// sample, so the binaural row's difference can be told from the machine's noise.
double decoder_seconds_per_sample(double seconds, std::string& error) {
    auto made = BinauralDecoder::create(BinauralDecoder::default_sofa_path, 3, bench_sample_rate, format_block);
    if (!made.decoder) {
        error = made.error;
        return -1.0;
    }
    std::vector<std::vector<float>> planes(16, std::vector<float>(format_block));
    std::uint32_t state = 12345;
    for (auto& p : planes)
        for (float& v : p) v = static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) / 16777216.0f - 0.5f;
    std::vector<const float*> in;
    for (auto& p : planes) in.push_back(p.data());
    std::vector<float> left(format_block), right(format_block);
    const long blocks = std::max(1L, static_cast<long>(seconds * bench_sample_rate / format_block));
    const double start = thread_cpu_seconds();
    for (long b = 0; b < blocks; ++b) made.decoder->process(in.data(), format_block, left.data(), right.data());
    return (thread_cpu_seconds() - start) / static_cast<double>(blocks * format_block);
}

}  // namespace

int run_formats_bench(const BenchOptions& options, const CommandIo& io) {
    const double seconds = std::clamp(options.seconds * 4.0, 0.5, 40.0);
    std::vector<OutputFormat> formats;
    std::string error;
    for (const char* name : {"stereo", "ambix:1", "ambix:2", "ambix:3", "binaural"}) formats.push_back(*parse_output_format(name, error));
    std::vector<double> best(formats.size(), 1e300);
    double decoder = 1e300;
    io.err << "ameoto bench formats: heavy rain (50 mm/h, umbrella and pond), " << format_block << "-frame blocks, "
           << format_rounds << " rounds of " << seconds << " s per format...\n";
    for (int round = 0; round < format_rounds; ++round) {
        for (std::size_t f = 0; f < formats.size(); ++f) {
            const double t = format_seconds_per_sample(formats[f], seconds, error);
            if (t < 0.0) {
                io.err << "ameoto bench formats: " << formats[f].name() << ": " << error << "\n";
                return exit_status::refused;
            }
            best[f] = std::min(best[f], t);
        }
        const double d = decoder_seconds_per_sample(seconds, error);
        if (d < 0.0) {
            io.err << "ameoto bench formats: the binaural decoder: " << error << "\n";
            return exit_status::refused;
        }
        decoder = std::min(decoder, d);
    }
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
    // Issue 21's target: third-order encoding of this scene plus the binaural decoder within 5 % of a core
    // more than stereo (48 kHz, 256 frames): the binaural row's difference, read off.
    const double binaural_extra = 100.0 * (best.back() - stereo) * bench_sample_rate;
    // The decoder alone is measured too: its cost is steady, while the rows' differences carry the machine's
    // noise (on a loaded machine ambix:3 has come out below stereo).
    const double decoder_core = 100.0 * decoder * bench_sample_rate;
    const double ambix3_extra = 100.0 * (best[formats.size() - 2] - stereo) * bench_sample_rate;
    if (options.json) {
        io.out << "{\"suite\":\"formats\",\"format\":\"binaural decoder alone\",\"channels\":2,\"block_frames\":" << format_block
               << ",\"ns_per_sample\":" << json_number(decoder * 1e9) << ",\"core_percent\":" << json_number(decoder_core) << "}\n";
    } else {
        char line[300];
        std::snprintf(line, sizeof line, "decoder   alone (16 -> 2): %6.0f ns/sample, %5.2f %% of a core at 48 kHz\n", decoder * 1e9, decoder_core);
        io.out << line;
        std::snprintf(line, sizeof line,
                      "target: binaural (ambix:3 + decoder) within 5 %% of a core more than stereo: %+.2f %% measured (ambix:3 %+.2f %% + "
                      "decoder %.2f %% = %+.2f %%), %s\n",
                      binaural_extra, ambix3_extra, decoder_core, ambix3_extra + decoder_core,
                      std::max(binaural_extra, ambix3_extra + decoder_core) <= 5.0 ? "met" : "NOT met");
        io.out << line;
    }
    return exit_status::ok;
}

}  // namespace ameoto::client
