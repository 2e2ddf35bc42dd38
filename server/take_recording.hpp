// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --record-score FILE: the take, written as it plays, for `ameoto render score FILE` to render again
// (protocol/take_messages.hpp says what the file holds). The audio thread puts every command the renderer
// accepted, with the sample it applies it at, into the bridge's queue (AudioBridge::enable_take; no
// allocation, lock or system call there); this drains it on the control thread and appends the messages
// to FILE with one write(2) per poll, so what was written survives SIGKILL (the kernel has it).
//
// Scene changes are built on the worker and reach the audio thread by pointer: the scene manager notes
// each one's full description here (note_load, note_swap) before it sends the command, and when the
// audio thread reports that command applied, the note is written at its sample.
//
// The output format (--format) is in /take/start, so the take renders again as it played: ambix:N as
// Ambisonics, binaural decoded to the two ears (ameoto's render_output), its limiter on the ears
// (server/realtime/binaural_stage.hpp); /listener/orientation is recorded like the other commands.
//
// Interface:
//   TakeRecording take;
//   if (!take.open(options)) return 1;          // first of all (an unwritable FILE stops ameotod at once):
//                                                // without --record-score: off, true. false: said why
//   if (!take.begin(first, bridge)) return 1;   // before audio starts: /take/start, and the bridge's queue
//   take.note_load(object, scene, config)       // the scene manager, before bridge.send(load_scene)
//   take.note_swap(object, kind, config)        // likewise for swap_surface / swap_liquid
//   take.forget(object)                         // the send failed: nothing was applied
//   take.drain();      // each poll: the applied commands, then /take/frames (the take holds all before it)
//   take.finish();     // after the backend stopped: the rest and /take/end, one log line
//
// Thread: the control thread (the one reader of the queue), and the main thread after the loop.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/render/renderer.hpp"
#include "protocol/take_messages.hpp"
#include "server/options.hpp"
#include "server/realtime/audio_bridge.hpp"

namespace ameoto {

struct FirstScene;

class TakeRecording {
public:
    // 2^16 commands: at the drain's 0.1 s, a backlog of 650 000 commands a second before one is lost.
    static constexpr std::size_t queue_records = 65536;

    TakeRecording() = default;
    ~TakeRecording();
    TakeRecording(const TakeRecording&) = delete;
    TakeRecording& operator=(const TakeRecording&) = delete;

    bool open(const DaemonOptions& options);
    bool begin(const FirstScene& first, AudioBridge& bridge);
    bool on() const { return fd_ >= 0; }
    void note_load(const void* object, const SceneDescription& scene, const RendererConfig& config);
    void note_swap(const void* object, CommandKind kind, const RendererConfig& config);
    void forget(const void* object);
    void drain();
    void finish();

private:
    void append(std::uint64_t frame, const std::string& address, const std::vector<protocol::OscArgument>& args);
    void write_pending();

    AudioBridge* bridge_ = nullptr;
    std::string path_;
    std::string format_ = "stereo";   // --format's name (OutputFormat::name())
    int fd_ = -1;
    double rate_ = 48000.0;
    std::multimap<const void*, protocol::TakeSceneChange> notes_;   // by the object the command carries
    std::vector<unsigned char> pending_;   // bytes of this poll, written in one write(2)
    std::uint64_t frames_written_ = 0;     // the last /take/frames
    std::uint64_t commands_ = 0, scenes_ = 0;
    bool write_failed_ = false;
};

}  // namespace ameoto
