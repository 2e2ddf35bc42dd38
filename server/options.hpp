// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ameotod's command line: every option validated, with units, in --help.
//
// Interface:
//   ParsedOptions p = parse_options(argc, argv);
//   if (p.show_help) print(usage()); else if (!p.error.empty()) fail(p.error); else run(p.options);

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/ip/udp.hpp>

#include "engine/scene/output_format.hpp"
#include "server/osc/sender_filter.hpp"

namespace ameoto {

enum class BackendChoice { automatic, jack, null };

struct DaemonOptions {
    int port = 7770;                      // UDP; 0 = any free port (printed at start)
    std::optional<int> tcp_port;          // OSC over TCP; none = off (default); 0 = any free port (printed)
    std::string bind = "127.0.0.1";       // UDP and TCP
    SenderFilter allow;                   // --allow: senders outside these networks are ignored (default: all)
    BackendChoice backend = BackendChoice::automatic;
    std::string jack_name = "ameoto";
    bool autoconnect = false;
    std::optional<std::string> output;    // null backend: WAV path, "-" for none; default: a new timestamped file
    double sample_rate = 48000.0;         // null backend, Hz
    int block_size = 256;                 // null backend, frames
    std::optional<bool> realtime;         // null backend pacing; default: paced unless --duration
    int realtime_priority = 70;           // null backend, paced: the render thread's SCHED_FIFO priority
                                          // 1..99, or 0 for normal scheduling (jackd's -P / --no-realtime)
    std::optional<double> duration_s;
    std::uint64_t seed = 0;
    int channels = 2;                     // the output format's (resolve_output_format sets it)
    std::optional<OutputFormat> format;   // --format; none: the scene file's `output format=`, else
                                          // --channels' meaning (stereo for 2, ring:N)
    std::string hrtf = "/usr/share/libmysofa/default.sofa";   // --hrtf: binaural's SOFA file (BinauralDecoder::default_sofa_path)
    bool channels_given = false;          // --channels on the command line (it and --format exclude each other)
    int node = 0;                         // --node K: only the scene's surfaces on node K (0: all)
    std::optional<std::int64_t> start_at_unix_ns;   // --start-at: JACK plays silence until then (start_gate.hpp)
    std::vector<boost::asio::ip::udp::endpoint> peers;   // --peers: the nodes this one conducts (peers.hpp)
    double peer_latency_s = 0.025;        // --peer-latency: how far ahead the conducted commands are timed
    std::string scene = "umbrella";       // a built-in scene, a NAME.scene in scene_folder (is_scene_name),
                                          // or else the path of a scene file (ending in .scene)
    std::optional<std::string> scene_folder;   // default: SceneStore::default_folder()
    std::optional<double> rain_mm_per_h;   // starting rain rate; default: the scene's
    bool fixed_detail = false;            // never shed detail by measured load (output as offline)
    std::optional<std::string> block_trace;   // write the slow audio callbacks here (block_trace.hpp)
    std::optional<std::string> record_score;  // write every command applied here, a score (take_recording.hpp)
    double block_trace_threshold = 0.5;   // a callback is slow past this fraction of its period
    // Level (docs/loudness.md): auto chooses each scene's level gain so its default rain plays at
    // target_lufs; physical keeps 1.0 = 100 Pa. The listening gain goes on top; the limiter before the output.
    bool level_auto = true;
    double target_lufs = -23.0;           // EBU R 128
    std::optional<double> gain_db;        // default: the scene's (`output gain=`, else 0 dB)
    std::optional<bool> limiter;          // default: on with level auto, off with level physical
    bool limiter_on() const { return limiter.value_or(level_auto); }
};

struct ParsedOptions {
    DaemonOptions options;
    bool show_help = false;
    bool show_version = false;
    std::string error;
};

ParsedOptions parse_options(int argc, const char* const* argv);
std::string usage();

}  // namespace ameoto
