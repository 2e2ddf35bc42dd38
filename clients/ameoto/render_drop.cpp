// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/render_drop.hpp"

#include "clients/ameoto/render_scene.hpp"
#include "clients/ameoto/render_score.hpp"

#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/progress_line.hpp"
#include "engine/render/loudness.hpp"
#include <sndfile.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/svg_plot.hpp"
#include "engine/core/random.hpp"
#include "engine/models/drop.hpp"
#include "engine/models/liquid.hpp"
#include "engine/models/membrane.hpp"

namespace ameoto::client {
namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

std::vector<std::string> liquid_names() {
    std::vector<std::string> names;
    for (const Liquid& l : liquids::presets()) names.push_back(l.name);
    return names;
}

}  // namespace

std::string render_usage() {
    return "usage: ameoto render drop --diameter MM -o FILE.wav [--speed M/S] [--material NAME]\n"
           "           [--liquid NAME] [--seconds S] [--rate HZ] [--seed N] [--x M --y M]\n"
           "           [--output-kind far-field|mass] [--channels 1|2 | --format F] [--coarse-steps N]\n"
           "           [--impact wet|seed] [--air on|off] [--quiet] [--plot FILE.svg]\n"
           "\n"
           "Renders one drop falling on the umbrella, offline (no server needed): a lattice drop of\n"
           "the chosen liquid strikes the canopy's membrane, may break up, and the canopy's sound is\n"
           "written to a 32-bit float WAV. Prints one summary line: duration, pieces at the end,\n"
           "peak level. On a terminal, progress goes to stderr unless --quiet.\n"
           "\n"
           "Options:\n"
           "  --diameter MM       drop diameter in mm, 0.1..8 (required; below about 1.15 mm a drop\n"
           "                      is one mass and cannot break)\n"
           "  -o, --output FILE   the WAV file to write (required)\n"
           "  --speed M/S         impact speed in m/s, 0.1..30, or 0 for the drop's terminal speed\n"
           "                      (default 0)\n"
           "  --material NAME     canopy material: " +
           joined(membrane_material_names()) +
           " (default nylon;\n"
           "                      seed-nylon runs 27 sub-steps per sample: slow)\n"
           "  --liquid NAME       " +
           joined(liquid_names()) +
           " (default water)\n"
           "  --seconds S         duration in s, 0.01..60 (default 1)\n"
           "  --rate HZ           sample rate in Hz, 8000..192000 (default 48000)\n"
           "  --seed N            picks the impact point when --x/--y are not given, 0..2^64-1\n"
           "                      (default 1)\n"
           "  --x M, --y M        impact point in m, canopy coordinates (from the shaft; the\n"
           "                      default canopy is 8 panels of 0.5 m); both or neither\n"
           "  --output-kind K     far-field: the pressure at a listener 0.3 m under the shaft\n"
           "                      (1.0 = 100 Pa; default); mass: the seed's single-mass pickup,\n"
           "                      the displacement of the membrane mass under the impact point\n"
           "  --channels N        1 (mono) or 2 (two ears 0.18 m apart; default 1)\n"
           "  --format F          ring:1 (mono), ears (as --channels 2), stereo (panned), ring:N, or\n"
           "                      ambix:ORDER (1..3: 4, 9 or 16 channels, ACN/SN3D; docs/output-formats.md)\n"
           "  --coarse-steps N    1..64 samples a splash wholly in the air (touching nothing) may\n"
           "                      take as one step (default 4; 1: every piece every sample). The\n"
           "                      sound is the same to the bit until a piece lands again, then\n"
           "                      differs by about 1 % (docs/drop.md, \"Coarse steps for a splash in flight\")\n"
           "  --impact MODEL      how the drop's masses meet the membrane: wet (default: stopped\n"
           "                      as a liquid is, impulse m V, spreading; docs/impacts.md) or seed\n"
           "                      (the seed's elastic exchange: they bounce, impulse about 2 m V)\n"
           "  --air on|off        on (default): the canopy in air, its air-loaded modes heard as\n"
           "                      dipoles without a baffle (docs/canopy-air.md, \"In air\"); off:\n"
           "                      the lattice in vacuum under the baffled Rayleigh sum (the seed's\n"
           "                      model)\n"
           "  --quiet             no progress on stderr\n"
           "  --plot FILE.svg     also write a plot: pieces over time, a side view of the drop's\n"
           "                      masses at a few times, the waveform and the spectrogram\n"
           "\n"
           "Exit status: 0 rendered; 1 the render failed (file not written, configuration refused);\n"
           "2 usage error.\n"
           "\n"
           "Examples:\n"
           "  ameoto render drop --diameter 5 -o drop.wav\n"
           "  ameoto render drop --diameter 3 --speed 4 --material vinyl --channels 2 -o d.wav --plot d.svg\n"
           "  ameoto render drop --diameter 2 --liquid milk --x 0.2 --y 0 --output-kind mass -o m.wav\n"
           "  ameoto render drop --diameter 4 --impact seed -o seed.wav\n";
}

RenderParse parse_render_drop_options(const CommandWords& words, RenderDropOptions& o, std::string& error) {
    bool have_diameter = false, channels_given = false;
    OptionReader reader(words);
    for (auto kind = reader.next_word(); kind != OptionReader::Word::end; kind = reader.next_word()) {
        // The word as typed for the messages below: the option's name, or the positional word.
        const std::string word = kind == OptionReader::Word::positional ? reader.positional() : reader.name();
        const std::string& name = reader.name();
        std::string value;
        auto take_value = [&] { return reader.value_into(value, error); };
        auto no_value = [&] { return reader.flag_into(error); };
        auto number_in = [&](double lo, double hi, const std::string& unit) { return reader.number_into(lo, hi, unit, error); };
        if (name == "--help" || name == "-h") return RenderParse::help;
        if (name == "--quiet") {
            if (!no_value()) return RenderParse::error;
            o.quiet = true;
        } else if (name == "--diameter") {
            const auto v = number_in(0.1, 8.0, "mm");
            if (!v) return RenderParse::error;
            o.diameter_mm = *v;
            have_diameter = true;
        } else if (name == "--speed") {
            const auto v = number_in(0.0, 30.0, "m/s");
            if (!v) return RenderParse::error;
            if (*v > 0.0 && *v < 0.1) {
                error = "--speed: " + short_number(*v) + " m/s is too slow: 0 (terminal speed) or 0.1..30 m/s";
                return RenderParse::error;
            }
            o.speed_m_per_s = *v;
        } else if (name == "--impact") {
            if (!take_value()) return RenderParse::error;
            const std::optional<ImpactModel> model = find_impact_model(value);
            if (!model) {
                error = "--impact: unknown impact model '" + value + "' (known: wet, seed)";
                return RenderParse::error;
            }
            o.impact = *model;
        } else if (name == "--air") {
            if (!take_value()) return RenderParse::error;
            if (value != "on" && value != "off") {
                error = "--air: '" + value + "' is not on or off";
                return RenderParse::error;
            }
            o.air = value == "on";
        } else if (name == "--material") {
            if (!take_value()) return RenderParse::error;
            if (!membrane_material(value)) {
                error = "--material: unknown material '" + value + "' (known: " + joined(membrane_material_names()) + ")";
                return RenderParse::error;
            }
            o.material = value;
        } else if (name == "--liquid") {
            if (!take_value()) return RenderParse::error;
            if (!find_liquid(value)) {
                error = "--liquid: unknown liquid '" + value + "' (known: " + joined(liquid_names()) + ")";
                return RenderParse::error;
            }
            o.liquid = value;
        } else if (name == "--seconds") {
            const auto v = number_in(0.01, 60.0, "s");
            if (!v) return RenderParse::error;
            o.seconds = *v;
        } else if (name == "--rate") {
            if (!take_value()) return RenderParse::error;
            const auto v = parse_unsigned(value);
            if (!v || *v < 8000 || *v > 192000) {
                error = "--rate: '" + value + "' is not a sample rate in 8000..192000 Hz (an integer)";
                return RenderParse::error;
            }
            o.rate = static_cast<int>(*v);
        } else if (name == "--coarse-steps") {
            if (!take_value()) return RenderParse::error;
            const auto v = parse_unsigned(value);
            if (!v || *v < 1 || *v > 64) {
                error = "--coarse-steps: '" + value + "' is not a whole number of samples in 1..64";
                return RenderParse::error;
            }
            o.coarse_steps = static_cast<int>(*v);
        } else if (name == "--seed") {
            if (!take_value()) return RenderParse::error;
            const auto v = parse_unsigned(value);
            if (!v) {
                error = "--seed: '" + value + "' is not an integer in 0..18446744073709551615";
                return RenderParse::error;
            }
            o.seed = *v;
        } else if (name == "--x" || name == "--y") {
            const auto v = number_in(-10.0, 10.0, "m");
            if (!v) return RenderParse::error;
            (name == "--x" ? o.x : o.y) = *v;
        } else if (name == "--output-kind") {
            if (!take_value()) return RenderParse::error;
            if (value == "far-field") {
                o.output = SceneOutput::far_field;
            } else if (value == "mass") {
                o.output = SceneOutput::mass_pickup;
            } else {
                error = "--output-kind: '" + value + "' is not far-field or mass";
                return RenderParse::error;
            }
        } else if (name == "--channels") {
            if (!take_value()) return RenderParse::error;
            if (value != "1" && value != "2") {
                error = "--channels: '" + value + "' is not 1 or 2";
                return RenderParse::error;
            }
            if (o.format) {
                error = "give --format or --channels, not both";
                return RenderParse::error;
            }
            o.channels = value == "1" ? 1 : 2;
            channels_given = true;
        } else if (name == "--format") {
            if (!take_value()) return RenderParse::error;
            std::string why;
            const auto f = parse_output_format(value, why);
            if (!f) {
                error = "--format: " + why;
                return RenderParse::error;
            }
            if (f->kind == OutputKind::binaural) {
                error = "--format binaural: render drop does not decode to two ears (ears gives two points; "
                        "ameoto render scene --format binaural decodes)";
                return RenderParse::error;
            }
            if (channels_given) {
                error = "give --format or --channels, not both";
                return RenderParse::error;
            }
            o.format = *f;
            o.channels = f->channels;
        } else if (name == "-o" || name == "--output") {
            if (!take_value()) return RenderParse::error;
            if (value.empty()) {
                error = name + " needs a file name";
                return RenderParse::error;
            }
            o.wav_path = value;
        } else if (name == "--plot") {
            if (!take_value()) return RenderParse::error;
            if (value.empty()) {
                error = "--plot needs a file name";
                return RenderParse::error;
            }
            o.plot_path = value;
        } else if (word.starts_with("-")) {
            error = "unknown option '" + name + "'";
            return RenderParse::error;
        } else {
            error = "unexpected argument '" + word + "'";
            return RenderParse::error;
        }
    }
    if (!have_diameter) {
        error = "--diameter MM is required";
        return RenderParse::error;
    }
    if (o.wav_path.empty()) {
        error = "-o FILE.wav is required";
        return RenderParse::error;
    }
    if (o.x.has_value() != o.y.has_value()) {
        error = "--x and --y go together: give both or neither";
        return RenderParse::error;
    }
    return RenderParse::run;
}

namespace {

SNDFILE* open_wav(const std::string& path, int channels, int rate, std::string& error) {
    SF_INFO info{};
    info.samplerate = rate;
    info.channels = channels;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
    if (!f) error = "cannot open " + path + " for writing: " + sf_strerror(nullptr);
    return f;
}

bool write_wav(SNDFILE* f, const std::string& path, const std::vector<float>& interleaved, int channels, std::string& error) {
    const sf_count_t frames = static_cast<sf_count_t>(interleaved.size() / static_cast<std::size_t>(channels));
    const sf_count_t written = sf_writef_float(f, interleaved.data(), frames);
    if (written != frames) error = "cannot write " + path + ": " + sf_strerror(f);
    if (sf_close(f) != 0 && error.empty()) error = "cannot close " + path;
    return error.empty();
}

struct Snapshot {
    double time = 0.0;
    std::vector<SceneMass> masses;
};

std::string plot_svg(const RenderDropOptions& o, const std::vector<double>& times, const std::vector<double>& pieces,
                     const std::vector<Snapshot>& snapshots, const std::vector<float>& mono) {
    const std::string title = short_number(o.diameter_mm) + " mm " + o.liquid + " drop on " + o.material +
                              (o.speed_m_per_s > 0.0 ? ", " + short_number(o.speed_m_per_s) + " m/s" : ", terminal speed");
    SvgPlot plot(900, 1010, title);
    plot.series({70, 55, 800, 140}, times, pieces, "pieces", "time (s)");
    std::vector<PlotPoint> points;
    std::string label = "drop masses, side view, at";
    for (std::size_t k = 0; k < snapshots.size(); ++k) {
        label += (k ? ", " : " ") + fixed(snapshots[k].time * 1e3, 1) + " ms";
        for (const SceneMass& m : snapshots[k].masses)
            points.push_back(PlotPoint{m.position.x * 1e3, m.position.z * 1e3, static_cast<int>(k)});
    }
    label += " (colours in that order)";
    plot.scatter({70, 240, 800, 280}, points, label, "x (mm)", "z (mm)");
    plot.waveform({70, 565, 800, 150}, mono, static_cast<double>(o.rate));
    plot.spectrogram({70, 760, 800, 210}, mono, static_cast<double>(o.rate));
    return plot.str();
}

}  // namespace

int run_render(const CommandWords& words, const CommandIo& io) {
    if (words.empty()) {
        io.err << "ameoto render: what to render? (ameoto render drop ...; see ameoto render --help)\n";
        return exit_status::usage;
    }
    if (words[0] == "--help" || words[0] == "-h" || words[0] == "help") {
        io.out << render_usage() << "\n" << render_scene_usage() << "\n" << render_score_usage();
        return exit_status::ok;
    }
    if (words[0] == "scene") {
        RenderSceneOptions so;
        std::string scene_error;
        switch (parse_render_scene_options(CommandWords(words.begin() + 1, words.end()), so, scene_error)) {
            case RenderParse::help: io.out << render_scene_usage(); return exit_status::ok;
            case RenderParse::error:
                io.err << "ameoto render scene: " << scene_error << "\n(see ameoto render scene --help)\n";
                return exit_status::usage;
            case RenderParse::run: return run_render_scene(so, io);
        }
    }
    if (words[0] == "score") {
        RenderScoreOptions so;
        std::string score_error;
        switch (parse_render_score_options(CommandWords(words.begin() + 1, words.end()), so, score_error)) {
            case RenderParse::help: io.out << render_score_usage(); return exit_status::ok;
            case RenderParse::error:
                io.err << "ameoto render score: " << score_error << "\n(see ameoto render score --help)\n";
                return exit_status::usage;
            case RenderParse::run: return run_render_score(so, io);
        }
    }
    if (words[0] != "drop") {
        io.err << "ameoto render: unknown subject '" << words[0] << "': drop, scene or score (see ameoto render --help)\n";
        return exit_status::usage;
    }
    RenderDropOptions o;
    std::string error;
    switch (parse_render_drop_options(CommandWords(words.begin() + 1, words.end()), o, error)) {
        case RenderParse::help: io.out << render_usage(); return exit_status::ok;
        case RenderParse::error: io.err << "ameoto render drop: " << error << "\n(see ameoto render --help)\n"; return exit_status::usage;
        case RenderParse::run: break;
    }

    const auto start = std::chrono::steady_clock::now();
    DropOnCanopyConfig config;
    config.sample_rate = o.rate;
    config.material = *membrane_material(o.material);
    config.liquid = *find_liquid(o.liquid);
    config.output = o.output;
    config.channels = o.channels;
    if (o.format)
        config.listener = o.format->kind == OutputKind::ambix  ? ListenerStyle::ambix
                          : o.format->kind == OutputKind::ears ? ListenerStyle::ears
                                                               : ListenerStyle::panned;
    config.coarse_steps = o.coarse_steps;
    config.impact = o.impact;
    config.air = o.air;
    config.capacity = 1;
    config.max_diameter = o.diameter_mm * 1e-3 * (1.0 + 1e-9);   // build only the lattices this drop needs
    config.retire_below_m = -1e9;                                 // offline: follow every piece to the end
    config.max_lifetime_s = 0.0;
    std::optional<DropOnCanopy> scene;
    try {
        scene.emplace(config);
    } catch (const std::exception& e) {
        io.err << "ameoto render drop: " << e.what() << "\n";
        return exit_status::refused;
    }
    double x = 0.0, y = 0.0;
    if (o.x) {
        x = *o.x;
        y = *o.y;
        if (scene->canopy().locate(x, y).panel < 0) {
            io.err << "ameoto render drop: (" << x << ", " << y << ") m is not on the canopy (" << scene->canopy().panel_count()
                   << " panels of " << scene->canopy().geometry().radius_m << " m from the shaft)\n";
            return exit_status::usage;
        }
    } else {
        Random rng(o.seed);
        const Point2 p = scene->canopy().sample_point(rng);
        x = p.x;
        y = p.y;
    }
    if (o.output == SceneOutput::mass_pickup) {
        // The seed's pickup: the membrane mass under the impact (each panel is its own membrane, so a
        // pickup on another panel would hear nothing). Rebuilt with that point, off any audio thread.
        config.pickup_x = x;
        config.pickup_y = y;
        scene.reset();
        scene.emplace(config);
    }
    const double diameter = o.diameter_mm * 1e-3;
    const double speed = o.speed_m_per_s > 0.0 ? o.speed_m_per_s : arrival_speed(diameter, config.liquid.density);
    if (!scene->drop(diameter, speed, x, y)) {
        io.err << "ameoto render drop: the drop could not be placed\n";
        return exit_status::refused;
    }

    // Open the outputs first, so a bad path fails before the render rather than after it.
    SNDFILE* wav = open_wav(o.wav_path, o.channels, o.rate, error);
    if (!wav) {
        io.err << "ameoto render drop: " << error << "\n";
        return exit_status::refused;
    }
    if (o.format)   // what the channels are (the --channels formats say it in --help)
        sf_set_string(wav, SF_STR_COMMENT, ("ameoto render drop. Channels: " + output_channel_summary(*o.format)).c_str());
    std::ofstream svg;
    if (!o.plot_path.empty()) {
        svg.open(o.plot_path, std::ios::binary | std::ios::trunc);
        if (!svg) {
            sf_close(wav);
            std::remove(o.wav_path.c_str());
            io.err << "ameoto render drop: cannot open " << o.plot_path << " for writing\n";
            return exit_status::refused;
        }
    }

    const long total = std::max(1L, std::lround(o.seconds * o.rate));
    const int channels = o.channels;
    std::vector<std::vector<float>> planar(static_cast<std::size_t>(channels), std::vector<float>(static_cast<std::size_t>(total)));
    const bool plotting = !o.plot_path.empty();
    std::vector<double> times, pieces;
    std::vector<Snapshot> snapshots;
    const double snapshot_times[] = {0.0, 1e-3, 3e-3, 10e-3, 30e-3};
    std::size_t next_snapshot = 0;
    ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr, o.rate);
    constexpr long block = 64;
    std::vector<float*> out(static_cast<std::size_t>(channels));
    for (long done = 0; done < total;) {
        const double t = static_cast<double>(done) / o.rate;
        if (plotting) {
            times.push_back(t);
            pieces.push_back(scene->stats().pieces);
            if (next_snapshot < std::size(snapshot_times) && t >= snapshot_times[next_snapshot]) {
                snapshots.push_back(Snapshot{t, scene->snapshot()});
                ++next_snapshot;
            }
        }
        const long n = std::min(block, total - done);
        for (int c = 0; c < channels; ++c) out[static_cast<std::size_t>(c)] = planar[static_cast<std::size_t>(c)].data() + done;
        scene->process(static_cast<int>(n), out.data());
        done += n;
        progress.show(done, total);
    }
    progress.clear();
    const DropOnCanopyStats stats = scene->stats();
    if (plotting) {
        times.push_back(static_cast<double>(total) / o.rate);
        pieces.push_back(stats.pieces);
    }

    std::vector<float> interleaved(static_cast<std::size_t>(total * channels));
    double peak = 0.0;
    bool finite = true;
    for (long i = 0; i < total; ++i)
        for (int c = 0; c < channels; ++c) {
            const float s = planar[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
            if (!std::isfinite(s)) finite = false;
            peak = std::max(peak, static_cast<double>(std::fabs(s)));
            interleaved[static_cast<std::size_t>(i * channels + c)] = s;
        }
    if (!write_wav(wav, o.wav_path, interleaved, channels, error)) {
        io.err << "ameoto render drop: " << error << "\n";
        return exit_status::refused;
    }
    if (plotting) {
        svg << plot_svg(o, times, pieces, snapshots, planar[0]);
        svg.close();
        if (!svg) {
            io.err << "ameoto render drop: cannot write " << o.plot_path << "\n";
            return exit_status::refused;
        }
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string level = peak > 0.0 ? fixed(20.0 * std::log10(peak), 1) + " dBFS" : "silent";
    io.out << "rendered " << fixed(static_cast<double>(total) / o.rate, 3) << " s of a " << short_number(o.diameter_mm)
           << " mm " << o.liquid << " drop at " << fixed(speed, 2) << " m/s on " << o.material << " at (" << fixed(x, 3)
           << ", " << fixed(y, 3) << ") m to " << o.wav_path << ": " << stats.pieces << " piece"
           << (stats.pieces == 1 ? "" : "s") << " at the end, peak " << level << " (" << fixed(peak, 4) << "), "
           << stats.collisions << " collisions, " << fixed(elapsed, 2) << " s to render" << (finite ? "" : ", NON-FINITE samples")
           << "\n";
    LoudnessMeter loudness(channels, o.rate, LoudnessMeter::integrated | LoudnessMeter::peaks);
    loudness.add(interleaved.data(), static_cast<std::size_t>(total));
    const double integrated = loudness.integrated_lufs();
    io.out << "loudness " << (std::isfinite(integrated) ? fixed(integrated, 2) + " LUFS integrated" : std::string("below the -70 LUFS gate"))
           << ", true peak " << (std::isfinite(loudness.true_peak_dbfs()) ? fixed(loudness.true_peak_dbfs(), 2) + " dBTP" : std::string("none"))
           << " (physical scale: 1.0 = 100 Pa, 0 dBFS = 133.98 dB SPL)\n";
    return finite ? exit_status::ok : exit_status::refused;
}

}  // namespace ameoto::client
