// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A recorded take (ameotod --record-score FILE), read back by `ameoto render score FILE`: the one place
// that says what its messages hold, so the writer and the reader cannot disagree.
//
// The file is scsynth's binary score (what SuperCollider's Score.write writes): OSC bundles one after
// the other, each preceded by its size as a big-endian int32, its timetag the time from the start of
// the take in seconds (OSC's 32.32 fixed point, no 1900 epoch). Each bundle holds one message:
//   /take/start   i:version d:rate_hz i:channels h:seed i:node i:limiter d:full_scale_pa d:level_gain_db
//                 i:adaptive_detail s:scene s:format
//                 -- first, at 0 s: the state the stream started from; format: the output format's text
//                 (output_format.hpp: "stereo", "ring:6", "ambix:1", "binaural", ...). Take format 1 (before
//                 2026-12-02) has no format: read as today, the renderer's channels alone (stereo, a ring)
//   /take/command h:frame i:kind d d d d           -- a command as the engine applied it: its kind
//                 (CommandKind) and its four values in SI units (command.hpp), at the sample it took effect;
//                 orientation (/listener/orientation: yaw, pitch, roll in radians) too, its rotation rebuilt
//                 by the reader for the format's order
//   /take/scene   h:frame i:kind d:level_gain_db s:scene MATERIAL LIQUID
//                 -- a scene swapped in at that sample: kind load_scene (scene: its full description, built
//                 on the stream's base with that material for its umbrella and that liquid), or
//                 swap_surface / swap_liquid (the first scene's umbrella with MATERIAL and LIQUID)
//   /take/frames  h:frames i:lost                  -- about every 0.1 s: the take holds every command applied
//                 before this sample; `lost`: commands the recorder's queue had no room for (then the take
//                 is not the stream)
//   /take/end     h:frames i:lost                  -- the last message of a take that was closed
// MATERIAL is s:name d:areal_density d:tension d:mass_damping d:stiffness_damping d:link_stiffness
// d:total_mass d:link_damping (membrane.hpp); LIQUID is s:name d:density d:surface_tension d:viscosity.
// The frame is carried as an integer besides the timetag, so the sample is exact at any rate.
//
// Interface (any thread; allocates):
//   std::vector<unsigned char> bytes = take_element(frame, rate, address, args);   // one size-prefixed bundle
//   args = take_start_arguments(start)  ...  read_take_start(message, start)  -> "" or the reason
//   args = take_command_arguments(frame, command)  ...  read_take_command(message, frame, command)
//   args = take_scene_arguments(change)  ...  read_take_scene(message, change)
//   args = take_frames_arguments(frames, lost)  ...  read_take_frames(message, frames, lost)

#include <cstdint>
#include <string>
#include <vector>

#include "engine/models/liquid.hpp"
#include "engine/models/membrane.hpp"
#include "engine/render/command.hpp"
#include "protocol/osc_codec.hpp"

namespace ameoto::protocol {

inline constexpr int take_format_version = 2;   // 1: no format in /take/start (still read)
inline constexpr const char* take_start_address = "/take/start";
inline constexpr const char* take_command_address = "/take/command";
inline constexpr const char* take_scene_address = "/take/scene";
inline constexpr const char* take_frames_address = "/take/frames";
inline constexpr const char* take_end_address = "/take/end";

struct TakeStart {
    double rate_hz = 48000.0;
    int channels = 2;
    std::uint64_t seed = 0;
    int node = 0;
    bool limiter = false;
    double full_scale_pa = 100.0;
    double level_gain_db = 0.0;
    bool adaptive_detail = false;   // the live stream shed detail by load (then a render is at full detail)
    std::string scene;              // format_scene of the first scene (with --rain and --gain in it)
    std::string format = "stereo";  // the output format's text (OutputFormat::name()); "": read from a format-1 take
};

struct TakeSceneChange {
    std::uint64_t frame = 0;
    CommandKind kind = CommandKind::load_scene;   // load_scene, swap_surface or swap_liquid
    double level_gain_db = 0.0;                   // load_scene: the level gain it plays at
    std::string scene;                            // load_scene: format_scene of it
    MembraneMaterial material;
    Liquid liquid;
};

std::vector<unsigned char> take_element(std::uint64_t frame, double rate_hz, const std::string& address,
                                        const std::vector<OscArgument>& args);

std::vector<OscArgument> take_start_arguments(const TakeStart& start);
std::vector<OscArgument> take_command_arguments(std::uint64_t frame, const Command& command);
std::vector<OscArgument> take_scene_arguments(const TakeSceneChange& change);
std::vector<OscArgument> take_frames_arguments(std::uint64_t frames, std::uint64_t lost);

// Each returns "" when the message is well formed, else the reason (which argument, what it should be).
std::string read_take_start(const DecodedMessage& m, TakeStart& start);
std::string read_take_command(const DecodedMessage& m, std::uint64_t& frame, Command& command);
std::string read_take_scene(const DecodedMessage& m, TakeSceneChange& change);
std::string read_take_frames(const DecodedMessage& m, std::uint64_t& frames, std::uint64_t& lost);

}  // namespace ameoto::protocol
