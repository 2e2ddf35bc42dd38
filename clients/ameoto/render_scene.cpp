// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/render_scene.hpp"

#include <sndfile.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "clients/ameoto/argument_types.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/progress_line.hpp"
#include "clients/ameoto/render_output.hpp"
#include "engine/render/level_choice.hpp"
#include "engine/render/loudness.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto::client {

std::string render_scene_usage() {
    return "usage: ameoto render scene -o FILE.wav [--scene NAME|FILE.scene] [--rain MM/H] [--seconds S]\n"
           "           [--rate HZ] [--seed N] [--channels N | --format F] [--level auto|physical]\n"
           "           [--hrtf FILE.sofa] [--loudness LUFS]\n"
           "           [--gain DB] [--limiter on|off] [--air on|off] [--impact wet|seed] [--quiet]\n"
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
           "  --channels N        1..16 (default 2): stereo for 2, else ring:N\n" +
           format_option_usage() +
           "  --hrtf FILE.sofa    binaural: the head-related impulse responses (AES69 SOFA; default\n"
           "                      /usr/share/libmysofa/default.sofa, MIT KEMAR; docs/binaural.md)\n" +
           "  --level auto|physical\n"
           "                      auto (default): a level gain chosen so the scene's default rain\n"
           "                      plays at --loudness (3 s of it rendered and measured first, as\n"
           "                      ameotod does; through the limiter when it is on, at most 12 dB\n"
           "                      more); --rain changes the rain, not the gain. physical:\n"
           "                      1.0 = 100 Pa at the listener (0 dBFS = 133.98 dB SPL)\n"
           "  --loudness LUFS     auto's target, -60..-5 LUFS integrated (default -23, EBU R 128)\n"
           "  --gain DB           listening gain on top, -80..80 dB (default: the scene's, else 0)\n"
           "  --limiter on|off    look-ahead limiter, ceiling -1 dBFS, 2 ms look-ahead and attack,\n"
           "                      100 ms release (default: on with --level auto, off with physical)\n"
           "  --air on|off        the umbrella's canopy in air (its air-loaded modes heard as dipoles,\n"
           "                      docs/canopy-air.md) or in vacuum, baffled (the seed's); default: the\n"
           "                      scene's (the built-in scenes: on; a file's umbrella air= key, whose\n"
           "                      default is on from scene version 5, off before)\n"
           "  --impact wet|seed   how drops meet the umbrella's canopy: wet (stopped as a liquid is,\n"
           "                      impulse m V; docs/impacts.md) or seed (the seed's elastic exchange);\n"
           "                      default: the scene's umbrella impact= key (wet when not given)\n"
           "  --quiet             no progress on stderr\n"
           "  -o FILE.wav         the output (32-bit float WAV)\n"
           "\n"
           "Prints the integrated loudness (EBU R 128) and the peak; the WAV's comment (LIST/INFO ICMT)\n"
           "says what 0 dBFS is in dB SPL at the listener.\n"
           "Exit status: 0 rendered; 1 the render failed (file, scene refused); 2 usage error.\n"
           "\n"
           "Examples:\n"
           "  ameoto render scene --scene pond --rain 1.5 --seconds 20 --rate 96000 -o pond.wav\n"
           "  ameoto render scene --scene street --channels 4 -o street.wav\n";
}

namespace {

// "level auto: default rain 1.5 mm/h measures -104.12 LUFS at the physical scale, level gain +81.12 dB, gain +0 dB:
// 0 dBFS = 52.86 dB SPL, limiter on": the WAV's comment and the last line printed.
std::string level_text(const RenderSceneOptions& o, const LevelChoice& level, double default_rain, double gain_db, double spl,
                       bool limiter) {
    std::string text;
    if (!o.level_auto) text = "level physical (1.0 = 100 Pa at the listener)";
    else if (!std::isfinite(level.measured_lufs)) text = "level auto: the default rain (" + short_number(default_rain) + " mm/h) is silent, level gain 0 dB";
    else
        text = "level auto: default rain " + short_number(default_rain) + " mm/h measures " + fixed(level.measured_lufs, 2) +
               " LUFS at the physical scale, target " + fixed(o.target_lufs, 1) + " LUFS, level gain " + (level.gain_db >= 0 ? "+" : "") +
               fixed(level.gain_db, 2) + " dB" +
               (level.limiter_db > 0.005 ? " (+" + fixed(level.limiter_db, 2) + " dB of it making up for the limiter)" : "");
    text += ", gain " + std::string(gain_db >= 0 ? "+" : "") + fixed(gain_db, 2) + " dB: 0 dBFS = " + fixed(spl, 2) +
            " dB SPL, limiter " + (limiter ? "on" : "off");
    return text;
}

}  // namespace

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
        } else if (name == "--impact") {
            if (!take_value()) return RenderParse::error;
            o.impact = find_impact_model(value);
            if (!o.impact) {
                error = "--impact: '" + value + "' is not wet or seed";
                return RenderParse::error;
            }
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
        } else if (name == "--level" || name == "--limiter") {
            if (!take_value()) return RenderParse::error;
            if (name == "--level" && value != "auto" && value != "physical") {
                error = "--level: '" + value + "' is not auto or physical";
                return RenderParse::error;
            }
            if (name == "--limiter" && value != "on" && value != "off") {
                error = "--limiter: '" + value + "' is not on or off";
                return RenderParse::error;
            }
            if (name == "--level") o.level_auto = value == "auto";
            else o.limiter = value == "on";
        } else if (name == "--loudness") {
            const auto v = number_in(-60.0, -5.0, "LUFS");
            if (!v) return RenderParse::error;
            o.target_lufs = *v;
        } else if (name == "--gain") {
            const auto v = number_in(-80.0, 80.0, "dB");
            if (!v) return RenderParse::error;
            o.gain_db = *v;
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
                if (!o.format.take_channels(static_cast<int>(*v), error)) return RenderParse::error;
            }
        } else if (name == "--hrtf") {
            if (!take_value() || !take_hrtf_option(value, o.hrtf, error)) return RenderParse::error;
        } else if (name == "--format") {
            if (!take_value()) return RenderParse::error;
            if (!o.format.take_format(value, error)) return RenderParse::error;
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
        if (o.gain_db) scene.gain_db = *o.gain_db;
        if (o.air)
            for (SurfaceDescription& s : scene.surfaces)
                if (s.kind == SurfaceKind::umbrella) s.air = *o.air;
        if (o.impact)
            for (SurfaceDescription& s : scene.surfaces)
                if (s.kind == SurfaceKind::umbrella) s.impact = *o.impact;
    } catch (const std::exception& e) {
        io.err << "ameoto render scene: " << e.what() << "\n";
        return exit_status::refused;
    }
    std::optional<Renderer> renderer;
    OutputFormat format;
    const double default_rain = scene.rain.rate_mm_per_h;
    LevelChoice level;
    const bool limiter = o.limiter.value_or(o.level_auto);
    try {
        RendererConfig base;
        base.sample_rate = o.rate;
        format = o.format.resolve(scene.output_format);
        apply_output_format(base, format);
        base.seed = o.seed;
        base.adaptive_lod = false;   // offline: reproducible, whatever the machine's load
        // Binaural: the limiter acts on the decoded ears (render_output.hpp), the bus is not limited.
        base.limiter = limiter && format.kind != OutputKind::binaural;
        // --level auto: measured at the scene's own rain, as ameotod does (level_choice.hpp), from the
        // same build of the umbrella as the render (umbrella_scene.hpp).
        const RendererConfig at_default = configure_for_scene(base, scene);
        const std::shared_ptr<const UmbrellaParts> parts = Renderer::make_parts(at_default);
        if (o.level_auto) level = choose_level(at_default, *parts, o.target_lufs);
        if (o.rain_mm_per_h) scene.rain.rate_mm_per_h = *o.rain_mm_per_h;
        RendererConfig config = configure_for_scene(base, scene);
        config.level_gain_db = level.gain_db;
        renderer.emplace(config, parts.get());
    } catch (const std::exception& e) {
        io.err << "ameoto render scene: " << e.what() << "\n";
        return exit_status::refused;
    }
    constexpr int block = 512;
    // Binaural: the renderer's third-order bus, decoded to two ears block by block (render_output.hpp;
    // built here, before any sample: libmysofa reads and resamples the SOFA file).
    std::string error;
    std::optional<RenderOutput> output = RenderOutput::make(format, renderer->config().channels, o.hrtf, o.rate, block, limiter, error);
    if (!output) {
        io.err << "ameoto render scene: " << error << "\n";
        return exit_status::refused;
    }
    SF_INFO info{};
    info.samplerate = o.rate;
    info.channels = format.channels;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* wav = sf_open(o.wav_path.c_str(), SFM_WRITE, &info);
    if (!wav) {
        io.err << "ameoto render scene: cannot open " << o.wav_path << " for writing: " << sf_strerror(nullptr) << "\n";
        return exit_status::refused;
    }
    const double spl = full_scale_spl_db(renderer->config().full_scale_pa, level.gain_db + scene.gain_db);
    const std::string calibration = level_text(o, level, default_rain, scene.gain_db, spl, limiter);
    sf_set_string(wav, SF_STR_SOFTWARE, "ameoto render scene");
    sf_set_string(wav, SF_STR_COMMENT, ("ameoto render scene: " + calibration +
                                        ". Samples are sound pressure at the listener: pressure in Pa = sample x 10^((0 dBFS in "
                                        "dB SPL - 93.98) / 20). Channels: " + output_channel_summary(format))
                                           .c_str());
    LoudnessMeter loudness(format.channels, o.rate, LoudnessMeter::integrated | LoudnessMeter::peaks);
    const long total = std::max(1L, std::lround(o.seconds * o.rate));
    const int channels = output->channels();   // the file's (2 for binaural; the renderer's bus is 16)
    std::vector<float> interleaved(static_cast<std::size_t>(block * channels));
    ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr, o.rate);
    double peak = 0.0;
    bool finite = true;
    std::uint64_t ears_clipped = 0;   // binaural: the ears' samples past full scale (the bus is not limited)
    for (long done = 0; done < total;) {
        const int n = static_cast<int>(std::min<long>(block, total - done));
        renderer->process(n, output->bus());
        output->finish(n);
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < channels; ++c) {
                const float s = output->channel(c)[i];
                if (!std::isfinite(s)) finite = false;
                peak = std::max(peak, static_cast<double>(std::fabs(s)));
                ears_clipped += std::fabs(s) > 1.0f;
                interleaved[static_cast<std::size_t>(i * channels + c)] = s;
            }
        loudness.add(interleaved.data(), static_cast<std::size_t>(n));
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
    const std::string peak_text = peak > 0.0 ? fixed(20.0 * std::log10(peak), 1) + " dBFS" : "silent";
    io.out << "rendered " << fixed(static_cast<double>(total) / o.rate, 3) << " s of scene '" << scene.name << "' at "
           << short_number(scene.rain.rate_mm_per_h) << " mm/h to " << o.wav_path << ": " << s.drops + s.surface_drops
           << " drops (umbrella: " << s.rain_tiers.full << " full, " << s.rain_tiers.template_ << " template, "
           << s.rain_tiers.texture << " texture; other surfaces: " << s.surface_drops << "), peak " << peak_text << ", "
           << fixed(elapsed, 2) << " s to render" << (finite ? "" : ", NON-FINITE samples") << "\n";
    const double integrated = loudness.integrated_lufs();
    io.out << "loudness " << (std::isfinite(integrated) ? fixed(integrated, 2) + " LUFS integrated" : std::string("below the -70 LUFS gate"))
           << ", true peak " << (std::isfinite(loudness.true_peak_dbfs()) ? fixed(loudness.true_peak_dbfs(), 2) + " dBTP" : std::string("none"))
           << ", " << (format.kind == OutputKind::binaural ? ears_clipped : s.clipped_samples) << " samples past full scale; " << calibration
           << "\n";
    return finite ? exit_status::ok : exit_status::refused;
}

}  // namespace ameoto::client
