// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/render_score.hpp"

#include <sndfile.h>
#include <unistd.h>

#include <algorithm>
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
#include "clients/ameoto/render_output.hpp"
#include "clients/ameoto/render_take.hpp"
#include "clients/ameoto/score_file.hpp"
#include "engine/models/canopy.hpp"
#include "engine/render/renderer.hpp"
#include "protocol/address_table.hpp"
#include "protocol/receive.hpp"

namespace ameoto::client {
namespace {

// A validated command and where it came from, for the render loop.
struct ScoreCommand {
    Command command;
};

std::string score_seconds_text(double s) {
    std::ostringstream o;
    o.precision(9);
    o << s;
    return o.str();
}

bool read_scene(const std::string& name, SceneDescription& scene, std::string& error) {
    try {
        if (auto built_in = builtin_scene(name)) {
            scene = *built_in;
            return true;
        }
        std::ifstream in(name, std::ios::binary);
        if (!in) {
            error = "cannot read " + name;
            return false;
        }
        std::ostringstream text;
        text << in.rdbuf();
        scene = parse_scene(text.str(), name);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

}  // namespace

std::string render_score_usage() {
    return "usage: ameoto render score FILE -o OUT.wav [--scene NAME|FILE.scene] [--rain MM/H]\n"
           "           [--seconds S] [--rate HZ] [--seed N] [--channels N | --format F]\n"
           "           [--block FRAMES] [--hrtf FILE.sofa] [--quiet]\n"
           "\n"
           "Renders a score of timed OSC messages offline (no server needed) with the engine ameotod\n"
           "runs, every message at its sample: round(time x rate). FILE is scsynth's binary score (what\n"
           "SuperCollider's Score.write writes: size-prefixed OSC bundles, timetags in seconds from the\n"
           "start) or a text score, one message a line: TIME /address arg ... (TIME in seconds; \"quoted\"\n"
           "words are strings; # starts a comment). Every message is validated as over UDP; one invalid\n"
           "message refuses the score (its time, place and reason) and nothing is written. /status,\n"
           "/version, /nodes, /notify, /reply/port, /sync, /quit and queries are ignored; messages that rebuild\n"
           "the scene (/scene/*, /material/*, /rain/dsd, /surface/*, /accuracy) are refused. Of what\n"
           "Score adds, /g_new is ignored and /c_set (the end marker) ends the render when --seconds is\n"
           "not given.\n"
           "\n"
           "Options:\n"
           "  --scene NAME        umbrella (default), pond, tin-roof, forest, street, or a scene file\n"
           "  --rain MM/H         rain rate at the start, 0..500 mm/h (default: the scene's)\n"
           "  --seconds S         length, 0.01..86400 s (default: the /c_set end marker, else the last\n"
           "                      message's time + 3 s)\n"
           "  --rate HZ           sample rate, 8000..192000 Hz (default 48000)\n"
           "  --seed N            random seed, 0..2^64-1 (default 1)\n"
           "  --channels N        1..16 (default 2): stereo for 2, else ring:N\n" +
           format_option_usage() +
           "                      /listener/orientation messages turn the head in any format but ears\n"
           "  --hrtf FILE.sofa    binaural: the head-related impulse responses (AES69 SOFA; default\n"
           "                      /usr/share/libmysofa/default.sofa, MIT KEMAR; docs/binaural.md)\n"
           "  --block FRAMES      frames per engine call, 1..8192 (default 512; the samples are the same\n"
           "                      at any block size; binaural's ears, decoded in blocks of this size,\n"
           "                      within float rounding)\n"
           "  --quiet             no progress on stderr\n"
           "  -o FILE.wav         the output (32-bit float WAV)\n"
           "\n"
           "A take recorded by `ameotod --record-score FILE` renders again from the state it names (its\n"
           "scene, seed, rate, output format and level; these options are then refused), every command and\n"
           "scene change at the sample the live engine applied it, for the take's length (--seconds\n"
           "changes it): sample for sample the live stream when it ran with --fixed-detail, else at\n"
           "full detail. A take cut short by a crash renders up to its last whole record.\n"
           "\n"
           "Exit status: 0 rendered; 1 the score, the scene or the file was refused; 2 usage error.\n"
           "\n"
           "Examples:\n"
           "  printf '0.5 /drop 3 0 0.15 0.05\\n1.0 /rain/rate 20\\n' > s.txt\n"
           "  ameoto render score s.txt --seconds 4 -o s.wav\n"
           "  ameoto render score rain.osc --rate 96000 -o rain.wav    # from Score.write\n"
           "  ameoto render score take.osc -o take-again.wav           # from ameotod --record-score\n";
}

RenderParse parse_render_score_options(const CommandWords& words, RenderScoreOptions& o, std::string& error) {
    OptionReader reader(words);
    for (auto kind = reader.next_word(); kind != OptionReader::Word::end; kind = reader.next_word()) {
        if (kind == OptionReader::Word::positional) {
            if (!o.score_path.empty()) {
                error = "unexpected argument '" + reader.positional() + "' (one score at a time)";
                return RenderParse::error;
            }
            o.score_path = reader.positional();
            continue;
        }
        const std::string& name = reader.name();
        if (o.setup_option.empty() && (name == "--scene" || name == "--rain" || name == "--rate" || name == "--seed" || name == "--channels"))
            o.setup_option = name;
        std::string value;
        auto take_value = [&] { return reader.value_into(value, error); };
        if (name == "--help" || name == "-h") return RenderParse::help;
        if (name == "--quiet") {
            if (!reader.flag_into(error)) return RenderParse::error;
            o.quiet = true;
        } else if (name == "--scene") {
            if (!take_value()) return RenderParse::error;
            if (!builtin_scene(value) && !value.ends_with(".scene")) {
                error = "--scene: '" + value + "' is neither a built-in scene (umbrella, pond, tin-roof, forest, street) nor a .scene file";
                return RenderParse::error;
            }
            o.scene = value;
        } else if (name == "--rain") {
            const auto v = reader.number_into(0.0, 500.0, "mm/h", error);
            if (!v) return RenderParse::error;
            o.rain_mm_per_h = *v;
        } else if (name == "--hrtf") {
            if (!take_value() || !take_hrtf_option(value, o.hrtf, error)) return RenderParse::error;
        } else if (name == "--format") {
            if (!take_value()) return RenderParse::error;
            if (!o.format.take_format(value, error)) return RenderParse::error;
        } else if (name == "--seconds") {
            const auto v = reader.number_into(0.01, 86400.0, "s", error);
            if (!v) return RenderParse::error;
            o.seconds = *v;
        } else if (name == "--rate" || name == "--seed" || name == "--channels" || name == "--block") {
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
            } else if (name == "--channels") {
                if (!v || *v < 1 || *v > 16) {
                    error = "--channels: '" + value + "' is not 1..16";
                    return RenderParse::error;
                }
                if (!o.format.take_channels(static_cast<int>(*v), error)) return RenderParse::error;
            } else {
                if (!v || *v < 1 || *v > 8192) {
                    error = "--block: '" + value + "' is not 1..8192 frames";
                    return RenderParse::error;
                }
                o.block = static_cast<int>(*v);
            }
        } else if (name == "-o" || name == "--output") {
            if (!take_value()) return RenderParse::error;
            if (value.empty()) {
                error = name + " needs a file name";
                return RenderParse::error;
            }
            o.wav_path = value;
        } else {
            error = "unknown option '" + name + "'";
            return RenderParse::error;
        }
    }
    if (o.score_path.empty()) {
        error = "which score? (ameoto render score FILE -o OUT.wav)";
        return RenderParse::error;
    }
    if (o.wav_path.empty()) {
        error = "-o FILE.wav is required";
        return RenderParse::error;
    }
    return RenderParse::run;
}

int run_render_score(const RenderScoreOptions& o, const CommandIo& io) {
    const auto started = std::chrono::steady_clock::now();
    const std::string me = "ameoto render score: ";
    const ScoreFile score = read_score_file(o.score_path);
    if (!score.error.empty()) {
        io.err << me << score.error << "\n";
        return exit_status::refused;
    }
    if (is_take(score)) {
        if (!o.setup_option.empty()) {
            io.err << me << o.score_path << " is a recorded take: it names its own scene, rain, rate, seed and output format ("
                   << o.setup_option << " cannot change them)\n";
            return exit_status::usage;
        }
        return run_render_take(o, score, io);
    }
    SceneDescription scene;
    std::string error;
    if (!read_scene(o.scene, scene, error)) {
        io.err << me << "--scene " << o.scene << ": " << error << "\n";
        return exit_status::refused;
    }
    if (o.rain_mm_per_h) scene.rain.rate_mm_per_h = *o.rain_mm_per_h;
    std::optional<Renderer> renderer;
    std::optional<Canopy> geometry;
    OutputFormat format;
    try {
        RendererConfig base;
        base.sample_rate = o.rate;
        format = o.format.resolve(scene.output_format);
        apply_output_format(base, format);
        base.seed = o.seed;
        base.adaptive_lod = false;   // offline: every drop at its full detail, whatever the machine's load
        const RendererConfig config = configure_for_scene(base, scene);
        renderer.emplace(config);
        // What /drop points are checked against, as ameotod checks them (server/scene_manager.cpp).
        geometry.emplace(config.canopy, config.material, 1.0 / config.sample_rate);
    } catch (const std::exception& e) {
        io.err << me << "--scene " << o.scene << ": " << e.what() << "\n";
        return exit_status::refused;
    }
    protocol::ProtocolContext context;
    const bool umbrella = std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                                      [](const SurfaceDescription& s) { return s.kind == SurfaceKind::umbrella; });
    context.surfaces = umbrella ? std::vector<std::string>{"umbrella"} : std::vector<std::string>{};
    context.on_surface = [&](const std::string&, double x, double y) { return geometry->locate(x, y).panel >= 0; };
    context.ambisonic_order = format.kind == OutputKind::ambix || format.kind == OutputKind::binaural ? format.order : 0;
    context.ears = format.kind == OutputKind::ears;   // the head cannot turn between its fixed ear points: refused

    // Every message checked before a sample is written.
    std::vector<Command> commands;
    SceneDescription record = scene;   // what the scene is at each message, as the daemon's record follows it
    std::optional<double> end_marker;
    int ignored = 0;
    for (std::size_t index = 0; index < score.messages.size(); ++index) {
        const ScoreMessage& m = score.messages[index];
        auto refuse = [&](const std::string& reason) {
            io.err << me << m.where << ", at " << score_seconds_text(m.seconds) << " s (message " << index + 1 << " in time order): "
                   << m.message.address << ": " << reason << "\nnothing was rendered\n";
            return exit_status::refused;
        };
        // What SuperCollider's Score writes of its own: /g_new 1 0 0, the default group (Score.new adds it
        // at time 0), and /c_set, the conventional end marker. scsynth's words, with no meaning here.
        if (m.message.address == "/c_set") {
            end_marker = std::max(end_marker.value_or(0.0), m.seconds);
            continue;
        }
        if (m.message.address == "/g_new") {
            ++ignored;
            continue;
        }
        const protocol::Validation v = protocol::validate(m.message, context);
        if (!v.ok) return refuse(v.reason);
        using protocol::Action;
        switch (v.request.action) {
            case Action::enqueue: {
                Command c = v.request.command;
                if (c.kind == CommandKind::sync) {
                    ++ignored;   // its only effect is a reply
                    continue;
                }
                if (protocol::changes_scene(c.kind)) {
                    SceneDescription next = protocol::scene_after(record, c);
                    if (const std::string why = validate_scene(next); !why.empty()) return refuse(why);
                    record = std::move(next);
                }
                c.timed = true;
                c.frame = static_cast<std::uint64_t>(std::llround(m.seconds * o.rate));
                commands.push_back(c);
                break;
            }
            case Action::status:
            case Action::quit:
            case Action::query:
            case Action::notify:
            case Action::version:
            case Action::nodes:
            case Action::on_block:
            case Action::reply_port: ++ignored; break;
            default:
                return refuse("rebuilds the scene, which a score cannot do in this version: give the render the scene "
                              "instead (--scene FILE.scene)");
        }
    }
    const double last = score.messages.empty() ? 0.0 : score.messages.back().seconds;
    const double seconds = o.seconds ? *o.seconds : end_marker ? std::max(0.01, *end_marker) : last + 3.0;
    const long total = std::max(1L, std::lround(seconds * o.rate));

    // Binaural: the third-order bus decoded to two ears, block by block (render_output.hpp), built before
    // the file is opened: a SOFA file that cannot be used leaves nothing behind.
    std::optional<RenderOutput> output = RenderOutput::make(format, renderer->config().channels, o.hrtf, o.rate, o.block, renderer->config().limiter, error);
    if (!output) {
        io.err << me << error << "\n";
        return exit_status::refused;
    }
    SF_INFO info{};
    info.samplerate = o.rate;
    info.channels = format.channels;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* wav = sf_open(o.wav_path.c_str(), SFM_WRITE, &info);
    if (!wav) {
        io.err << me << "cannot open " << o.wav_path << " for writing: " << sf_strerror(nullptr) << "\n";
        return exit_status::refused;
    }
    sf_set_string(wav, SF_STR_SOFTWARE, "ameoto render score");
    sf_set_string(wav, SF_STR_COMMENT, ("ameoto render score. Channels: " + output_channel_summary(format)).c_str());
    const int block = o.block;
    const int channels = output->channels();   // the file's (binaural: 2 ears of the renderer's 16-channel bus)
    std::vector<float> interleaved(static_cast<std::size_t>(block * channels));
    ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr, o.rate);
    // The renderer holds at most pending_capacity commands waiting for their sample: an engine call is cut
    // short before the command that would overfill it, and the block filled in pieces (cutting a call
    // changes no sample; the binaural decoder still gets whole blocks).
    constexpr std::size_t room = Renderer::pending_capacity / 2;
    std::size_t next = 0;
    double peak = 0.0;
    for (long done = 0; done < total;) {
        const long n = std::min<long>(block, total - done);
        for (long filled = 0; filled < n;) {
            long piece = n - filled;
            const long at = done + filled;
            std::size_t queued = 0;
            while (next < commands.size() && commands[next].frame < static_cast<std::uint64_t>(at + piece)) {
                if (queued == room) {
                    piece = std::max<long>(1, static_cast<long>(commands[next].frame) - at);
                    break;
                }
                Command c = commands[next++];
                // The head's rotation, built here off the renderer's calls as ameotod builds it (packet_dispatch.cpp).
                if (c.kind == CommandKind::orientation)
                    c.object = new AmbixRotation(AmbixRotation::from_orientation(c.values[0], c.values[1], c.values[2], format.order));
                renderer->schedule(c);
                ++queued;
            }
            renderer->process(static_cast<int>(piece), output->bus(static_cast<int>(filled)));
            for (RendererEvent e; renderer->poll_event(e);)   // the rotations come back to be freed
                if (e.kind == RendererEventKind::retired && e.object_type == RetiredObject::rotation) delete static_cast<AmbixRotation*>(e.object);
            filled += piece;
        }
        output->finish(static_cast<int>(n));
        for (long i = 0; i < n; ++i)
            for (int c = 0; c < channels; ++c) {
                const float s = output->channel(c)[i];
                peak = std::max(peak, static_cast<double>(std::fabs(s)));
                interleaved[static_cast<std::size_t>(i * channels + c)] = s;
            }
        if (sf_writef_float(wav, interleaved.data(), n) != n) {
            io.err << me << "cannot write " << o.wav_path << ": " << sf_strerror(wav) << "\n";
            sf_close(wav);
            return exit_status::refused;
        }
        done += n;
        progress.show(done, total);
    }
    progress.clear();
    if (sf_close(wav) != 0) {
        io.err << me << "cannot close " << o.wav_path << "\n";
        return exit_status::refused;
    }
    const RendererStats& st = renderer->stats();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    io.out << "rendered " << fixed(static_cast<double>(total) / o.rate, 3) << " s of " << (score.binary ? "binary" : "text")
           << " score " << o.score_path << " on scene '" << scene.name << "' to " << o.wav_path << ": " << commands.size()
           << " commands, " << ignored << " server-only messages ignored, " << st.drops + st.surface_drops << " drops, peak "
           << (peak > 0.0 ? fixed(20.0 * std::log10(peak), 1) + " dBFS" : std::string("silent")) << ", " << fixed(elapsed, 2)
           << " s\n";
    return exit_status::ok;
}

}  // namespace ameoto::client
