// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/render_take.hpp"

#include <sndfile.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/progress_line.hpp"
#include "clients/ameoto/render_output.hpp"
#include "engine/render/renderer.hpp"
#include "protocol/take_messages.hpp"

namespace ameoto::client {
namespace {

// One thing the take says the engine did, at its sample.
struct TakeEntry {
    std::uint64_t frame = 0;
    Command command;                                     // a plain command (when !scene)
    std::optional<protocol::TakeSceneChange> scene;      // a scene swapped in
    std::string where;
};

// The material a recorded load named, for its umbrella (presets resolve without it, as in ameotod).
std::optional<MembraneMaterial> recorded_material(const std::string& name, const void* context) {
    const auto& m = *static_cast<const MembraneMaterial*>(context);
    return m.name == name ? std::optional<MembraneMaterial>(m) : std::nullopt;
}

void free_take_retired(const RendererEvent& e) {
    if (e.kind != RendererEventKind::retired) return;
    if (e.object_type == RetiredObject::scene_surfaces) delete static_cast<SceneSurfaces*>(e.object);
    else if (e.object_type == RetiredObject::loaded_scene) delete static_cast<LoadedScene*>(e.object);
    else if (e.object_type == RetiredObject::umbrella_scene) delete static_cast<UmbrellaScene*>(e.object);
    else if (e.object_type == RetiredObject::rotation) delete static_cast<AmbixRotation*>(e.object);
}

// The object ameotod's worker built for this change (scene_manager.cpp: build_and_load, rebuild).
Command build_take_change(const protocol::TakeSceneChange& change, const RendererConfig& base, const Renderer& renderer,
                     const std::string& where) {
    Command c;
    c.kind = change.kind;
    if (change.kind == CommandKind::load_scene) {
        RendererConfig config = configure_for_scene(base, parse_scene(change.scene, where), recorded_material, &change.material);
        config.liquid = change.liquid;
        config.level_gain_db = change.level_gain_db;
        c.object = Renderer::make_loaded_scene(config).release();
    } else {
        RendererConfig config = renderer.config();
        config.material = change.material;
        config.liquid = change.liquid;
        c.object = Renderer::make_scene(config).release();
    }
    return c;
}

}  // namespace

bool is_take(const ScoreFile& score) {
    return !score.messages.empty() && score.messages.front().message.address == protocol::take_start_address;
}

int run_render_take(const RenderScoreOptions& o, const ScoreFile& score, const CommandIo& io) {
    const auto started = std::chrono::steady_clock::now();
    const std::string me = "ameoto render score: ";
    const ScoreMessage& head = score.messages.front();
    protocol::TakeStart start;
    if (const std::string why = protocol::read_take_start(head.message, start); !why.empty()) {
        io.err << me << head.where << ": /take/start: " << why << "\n";
        return exit_status::refused;
    }
    // Every message read before a sample is written.
    std::vector<TakeEntry> entries;
    std::optional<std::uint64_t> end_frame;
    std::uint64_t lost = 0;
    bool closed = false;
    for (std::size_t i = 1; i < score.messages.size(); ++i) {
        const ScoreMessage& m = score.messages[i];
        const std::string& address = m.message.address;
        std::string why;
        TakeEntry e;
        e.where = m.where;
        if (address == protocol::take_command_address) {
            why = protocol::read_take_command(m.message, e.frame, e.command);
        } else if (address == protocol::take_scene_address) {
            protocol::TakeSceneChange change;
            why = protocol::read_take_scene(m.message, change);
            e.frame = change.frame;
            e.scene = std::move(change);
        } else if (address == protocol::take_frames_address || address == protocol::take_end_address) {
            std::uint64_t frames = 0, lost_here = 0;
            why = protocol::read_take_frames(m.message, frames, lost_here);
            if (why.empty()) {
                end_frame = std::max(end_frame.value_or(0), frames);
                lost = std::max(lost, lost_here);
                closed |= address == protocol::take_end_address;
            }
        } else {
            why = "not a message of a take (a take holds only /take/... messages)";
        }
        if (!why.empty()) {
            io.err << me << m.where << ": " << address << ": " << why << "\nnothing was rendered\n";
            return exit_status::refused;
        }
        if (address == protocol::take_command_address || address == protocol::take_scene_address) entries.push_back(std::move(e));
    }
    // The order the engine applied them in: by sample, and in the file's order (the order the audio
    // thread took them) among equal samples, as the renderer's pending list keeps them.
    std::stable_sort(entries.begin(), entries.end(), [](const TakeEntry& a, const TakeEntry& b) { return a.frame < b.frame; });
    if (lost > 0)
        io.err << me << "warning: the recorder lost " << lost << " commands (its queue was full): the render is not the stream\n";
    if (!closed)
        io.err << me << "note: the take was not closed (ameotod was killed?): rendering the " << end_frame.value_or(0)
               << " frames it holds\n";
    const auto total = static_cast<long>(o.seconds ? std::llround(*o.seconds * start.rate_hz) : static_cast<long long>(end_frame.value_or(0)));
    if (total <= 0) {
        io.err << me << o.score_path << ": the take holds no audio (no /take/frames)\nnothing was rendered\n";
        return exit_status::refused;
    }

    // The output format it played in (take format 2); a format-1 take has only its channel count, and
    // renders as it always did: the renderer's channels (stereo for 2, a ring else).
    OutputFormat format = output_format_for_channels(start.channels);
    if (!start.format.empty()) {
        std::string why;
        const std::optional<OutputFormat> f = parse_output_format(start.format, why);
        if (!f) {
            io.err << me << head.where << ": /take/start: " << why << "\nnothing was rendered\n";
            return exit_status::refused;
        }
        RendererConfig made;   // the renderer's channels for it (binaural: its 16-channel bus, what the take names)
        apply_output_format(made, *f);
        if (made.channels != start.channels) {
            io.err << me << head.where << ": /take/start: " << start.channels << " channels, but " << start.format << " has "
                   << made.channels << "\nnothing was rendered\n";
            return exit_status::refused;
        }
        format = *f;
    }
    const bool binaural = format.kind == OutputKind::binaural;
    std::optional<Renderer> renderer;
    RendererConfig base;
    try {
        base.sample_rate = start.rate_hz;
        base.channels = start.channels;
        if (!start.format.empty()) apply_output_format(base, format);   // binaural: the 16-channel bus
        base.seed = start.seed;
        base.node = start.node;
        base.limiter = start.limiter && !binaural;   // binaural: the limiter acts on the ears (render_output.hpp)
        base.full_scale_pa = start.full_scale_pa;
        base.adaptive_lod = false;   // offline: every drop at its full detail
        RendererConfig config = configure_for_scene(base, parse_scene(start.scene, head.where + " (the take's scene)"));
        config.level_gain_db = start.level_gain_db;
        renderer.emplace(config);
    } catch (const std::exception& e) {
        io.err << me << head.where << ": the take's first scene: " << e.what() << "\nnothing was rendered\n";
        return exit_status::refused;
    }

    // Binaural: the bus decoded to two ears block by block (render_output.hpp), the limiter on the ears as
    // live; built before the file is opened. The take does not name the SOFA file: --hrtf (the default
    // set unless ameotod played another).
    const int block = o.block;
    std::string error;
    std::optional<RenderOutput> output = RenderOutput::make(format, renderer->config().channels, o.hrtf, static_cast<int>(std::lround(start.rate_hz)),
                                                            block, start.limiter, error);
    if (!output) {
        io.err << me << error << "\nnothing was rendered\n";
        return exit_status::refused;
    }
    SF_INFO info{};
    info.samplerate = static_cast<int>(std::lround(start.rate_hz));
    info.channels = output->channels();
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* wav = sf_open(o.wav_path.c_str(), SFM_WRITE, &info);
    if (!wav) {
        io.err << me << "cannot open " << o.wav_path << " for writing: " << sf_strerror(nullptr) << "\n";
        return exit_status::refused;
    }
    if (!start.format.empty())
        sf_set_string(wav, SF_STR_COMMENT, ("ameoto render score (a take). Channels: " + output_channel_summary(format)).c_str());
    auto give_up = [&](const std::string& text) {
        sf_close(wav);
        ::unlink(o.wav_path.c_str());
        io.err << me << text << "\nnothing was rendered\n";
        return exit_status::refused;
    };
    const int channels = output->channels();
    std::vector<float> interleaved(static_cast<std::size_t>(block * channels));
    ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr, info.samplerate);
    // As render_score.cpp: an engine call is cut short before a command that would overfill the renderer's
    // pending list, and the block filled in pieces (no sample changes; the decoder still gets whole blocks).
    constexpr std::size_t room = Renderer::pending_capacity / 2;
    std::size_t next = 0, scenes = 0, commands = 0;
    for (long done = 0; done < total;) {
        const long n = std::min<long>(block, total - done);
        for (long filled = 0; filled < n;) {
            long piece = n - filled;
            const long at = done + filled;
            std::size_t queued = 0;
            while (next < entries.size() && entries[next].frame < static_cast<std::uint64_t>(at + piece)) {
                if (queued == room) {
                    piece = std::max<long>(1, static_cast<long>(entries[next].frame) - at);
                    break;
                }
                const TakeEntry& e = entries[next++];
                Command c = e.command;
                if (e.scene) {
                    try {
                        c = build_take_change(*e.scene, base, *renderer, e.where);
                    } catch (const std::exception& x) {
                        return give_up(e.where + ": the scene change at frame " + std::to_string(e.frame) + ": " + x.what());
                    }
                    ++scenes;
                } else {
                    // The head's rotation, built off the renderer's calls as ameotod builds it (packet_dispatch.cpp).
                    if (c.kind == CommandKind::orientation)
                        c.object = new AmbixRotation(AmbixRotation::from_orientation(c.values[0], c.values[1], c.values[2], format.order));
                    ++commands;
                }
                c.timed = true;
                c.frame = e.frame;
                renderer->schedule(c);
                ++queued;
            }
            renderer->process(static_cast<int>(piece), output->bus(static_cast<int>(filled)));
            RendererEvent event;
            while (renderer->poll_event(event)) free_take_retired(event);
            filled += piece;
        }
        output->finish(static_cast<int>(n));
        for (long i = 0; i < n; ++i)
            for (int c = 0; c < channels; ++c) interleaved[static_cast<std::size_t>(i * channels + c)] = output->channel(c)[i];
        if (sf_writef_float(wav, interleaved.data(), n) != n) return give_up("cannot write " + o.wav_path + ": " + sf_strerror(wav));
        done += n;
        progress.show(done, total);
    }
    progress.clear();
    if (sf_close(wav) != 0) {
        io.err << me << "cannot close " << o.wav_path << "\n";
        return exit_status::refused;
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    io.out << "rendered the take " << o.score_path << " again: " << fixed(static_cast<double>(total) / start.rate_hz, 3) << " s, "
           << commands << " commands, " << scenes << " scene changes, "
           << (start.adaptive_detail ? "at full detail (the live stream could shed detail)" : "fixed detail as live")
           << ", to " << o.wav_path << " in " << fixed(elapsed, 2) << " s\n";
    return exit_status::ok;
}

}  // namespace ameoto::client
