// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/render_scene.hpp"

#include <sndfile.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "clients/ameoto/argument_types.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/progress_line.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto::client {

std::string render_scene_usage() {
    return "usage: ameoto render scene -o FILE.wav [--scene NAME|FILE.scene] [--rain MM/H] [--seconds S]\n"
           "           [--rate HZ] [--seed N] [--channels N] [--air on|off] [--quiet]\n"
           "\n"
           "Renders a rain scene offline (no server needed) with the engine ameotod runs: its surfaces,\n"
           "rain and listener, every drop at its level of detail. Same scene, seed and rate: the same\n"
           "samples, on any machine load.\n"
           "\n"
           "Options:\n"
           "  --scene NAME        umbrella (default), pond, tin-roof, forest, street, or a scene file\n"
           "                      (a path ending in .scene; format in docs/scenes.md)\n"
           "  --rain MM/H         rain rate, 0..500 mm/h (default: the scene's)\n"
           "  --seconds S         length, 0.01..3600 s (default 10)\n"
           "  --rate HZ           sample rate, 8000..192000 Hz (default 48000)\n"
           "  --seed N            random seed, 0..2^64-1 (default 1)\n"
           "  --channels N        1..16 (default 2)\n"
           "  --air on|off        the umbrella's canopy in air (its air-loaded modes heard as dipoles,\n"
           "                      docs/canopy.md) or in vacuum, baffled (the seed's); default: the\n"
           "                      scene's umbrella air= key (off when not given)\n"
           "  --quiet             no progress on stderr\n"
           "  -o FILE.wav         the output (32-bit float WAV)\n"
           "\n"
           "Exit status: 0 rendered; 1 the render failed (file, scene refused); 2 usage error.\n"
           "\n"
           "Examples:\n"
           "  ameoto render scene --scene pond --rain 1.5 --seconds 20 --rate 96000 -o pond.wav\n"
           "  ameoto render scene --scene street --channels 4 -o street.wav\n";
}

RenderParse parse_render_scene_options(const CommandWords& words, RenderSceneOptions& o, std::string& error) {
    OptionReader reader(words);
    for (auto kind = reader.next_word(); kind != OptionReader::Word::end; kind = reader.next_word()) {
        const std::string word = kind == OptionReader::Word::positional ? reader.positional() : reader.name();
        const std::string& name = reader.name();
        std::string value;
        auto take_value = [&] { return reader.value_into(value, error); };
        auto number_in = [&](double lo, double hi, const std::string& unit) { return reader.number_into(lo, hi, unit, error); };
        if (name == "--help" || name == "-h") return RenderParse::help;
        if (name == "--quiet") {
            if (!reader.flag_into(error)) return RenderParse::error;
            o.quiet = true;
        } else if (name == "--air") {
            if (!take_value()) return RenderParse::error;
            if (value != "on" && value != "off") {
                error = "--air: '" + value + "' is not on or off";
                return RenderParse::error;
            }
            o.air = value == "on";
        } else if (name == "--scene") {
            if (!take_value()) return RenderParse::error;
            if (!builtin_scene(value) && !value.ends_with(".scene")) {
                error = "--scene: '" + value + "' is neither a built-in scene (umbrella, pond, tin-roof, forest, street) nor a .scene file";
                return RenderParse::error;
            }
            o.scene = value;
        } else if (name == "--rain") {
            const auto v = number_in(0.0, 500.0, "mm/h");
            if (!v) return RenderParse::error;
            o.rain_mm_per_h = *v;
        } else if (name == "--seconds") {
            const auto v = number_in(0.01, 3600.0, "s");
            if (!v) return RenderParse::error;
            o.seconds = *v;
        } else if (name == "--rate" || name == "--seed" || name == "--channels") {
            if (!take_value()) return RenderParse::error;
            const auto v = parse_unsigned(value);
            if (name == "--rate") {
                if (!v || *v < 8000 || *v > 192000) {
                    error = "--rate: '" + value + "' is not a sample rate in 8000..192000 Hz (an integer)";
                    return RenderParse::error;
                }
                o.rate = static_cast<int>(*v);
            } else if (name == "--seed") {
                if (!v) {
                    error = "--seed: '" + value + "' is not an integer in 0..18446744073709551615";
                    return RenderParse::error;
                }
                o.seed = *v;
            } else {
                if (!v || *v < 1 || *v > 16) {
                    error = "--channels: '" + value + "' is not 1..16";
                    return RenderParse::error;
                }
                o.channels = static_cast<int>(*v);
            }
        } else if (name == "-o" || name == "--output") {
            if (!take_value()) return RenderParse::error;
            if (value.empty()) {
                error = name + " needs a file name";
                return RenderParse::error;
            }
            o.wav_path = value;
        } else if (word.starts_with("-")) {
            error = "unknown option '" + name + "'";
            return RenderParse::error;
        } else {
            error = "unexpected argument '" + word + "'";
            return RenderParse::error;
        }
    }
    if (o.wav_path.empty()) {
        error = "-o FILE.wav is required";
        return RenderParse::error;
    }
    return RenderParse::run;
}

int run_render_scene(const RenderSceneOptions& o, const CommandIo& io) {
    const auto start = std::chrono::steady_clock::now();
    SceneDescription scene;
    try {
        if (auto built_in = builtin_scene(o.scene)) {
            scene = *built_in;
        } else {
            std::ifstream in(o.scene, std::ios::binary);
            if (!in) {
                io.err << "ameoto render scene: cannot read " << o.scene << "\n";
                return exit_status::refused;
            }
            std::ostringstream text;
            text << in.rdbuf();
            scene = parse_scene(text.str(), o.scene);
        }
        if (o.rain_mm_per_h) scene.rain.rate_mm_per_h = *o.rain_mm_per_h;
        if (o.air)
            for (SurfaceDescription& s : scene.surfaces)
                if (s.kind == SurfaceKind::umbrella) s.air = *o.air;
    } catch (const std::exception& e) {
        io.err << "ameoto render scene: " << e.what() << "\n";
        return exit_status::refused;
    }
    std::optional<Renderer> renderer;
    try {
        RendererConfig base;
        base.sample_rate = o.rate;
        base.channels = o.channels;
        base.seed = o.seed;
        base.adaptive_lod = false;   // offline: reproducible, whatever the machine's load
        renderer.emplace(configure_for_scene(base, scene));
    } catch (const std::exception& e) {
        io.err << "ameoto render scene: " << e.what() << "\n";
        return exit_status::refused;
    }
    SF_INFO info{};
    info.samplerate = o.rate;
    info.channels = o.channels;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* wav = sf_open(o.wav_path.c_str(), SFM_WRITE, &info);
    if (!wav) {
        io.err << "ameoto render scene: cannot open " << o.wav_path << " for writing: " << sf_strerror(nullptr) << "\n";
        return exit_status::refused;
    }
    const long total = std::max(1L, std::lround(o.seconds * o.rate));
    constexpr int block = 512;
    const int channels = o.channels;
    std::vector<std::vector<float>> planar(static_cast<std::size_t>(channels), std::vector<float>(block));
    std::vector<float*> out(static_cast<std::size_t>(channels));
    for (int c = 0; c < channels; ++c) out[static_cast<std::size_t>(c)] = planar[static_cast<std::size_t>(c)].data();
    std::vector<float> interleaved(static_cast<std::size_t>(block * channels));
    ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr, o.rate);
    double peak = 0.0;
    bool finite = true;
    for (long done = 0; done < total;) {
        const int n = static_cast<int>(std::min<long>(block, total - done));
        renderer->process(n, out.data());
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < channels; ++c) {
                const float s = planar[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
                if (!std::isfinite(s)) finite = false;
                peak = std::max(peak, static_cast<double>(std::fabs(s)));
                interleaved[static_cast<std::size_t>(i * channels + c)] = s;
            }
        if (sf_writef_float(wav, interleaved.data(), n) != n) {
            io.err << "ameoto render scene: cannot write " << o.wav_path << ": " << sf_strerror(wav) << "\n";
            sf_close(wav);
            return exit_status::refused;
        }
        done += n;
        progress.show(done, total);
    }
    progress.clear();
    if (sf_close(wav) != 0) {
        io.err << "ameoto render scene: cannot close " << o.wav_path << "\n";
        return exit_status::refused;
    }
    const RendererStats& s = renderer->stats();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string level = peak > 0.0 ? fixed(20.0 * std::log10(peak), 1) + " dBFS" : "silent";
    io.out << "rendered " << fixed(static_cast<double>(total) / o.rate, 3) << " s of scene '" << scene.name << "' at "
           << short_number(scene.rain.rate_mm_per_h) << " mm/h to " << o.wav_path << ": " << s.drops + s.surface_drops
           << " drops (umbrella: " << s.rain_tiers.full << " full, " << s.rain_tiers.template_ << " template, "
           << s.rain_tiers.texture << " texture; other surfaces: " << s.surface_drops << "), peak " << level << ", "
           << fixed(elapsed, 2) << " s to render" << (finite ? "" : ", NON-FINITE samples") << "\n";
    return finite ? exit_status::ok : exit_status::refused;
}

}  // namespace ameoto::client
