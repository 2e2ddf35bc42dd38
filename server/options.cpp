// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/options.hpp"

#include <boost/asio/ip/address.hpp>

#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>
#include <time.h>

#include "engine/scene/scene_description.hpp"
#include "server/peers.hpp"

namespace ameoto {
namespace {

bool parse_int(std::string_view text, long long low, long long high, long long& out) {
    const auto result = std::from_chars(text.data(), text.data() + text.size(), out);
    return result.ec == std::errc() && result.ptr == text.data() + text.size() && out >= low && out <= high;
}

bool parse_double(const std::string& text, double low, double high, double& out) {
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return !text.empty() && end == text.c_str() + text.size() && std::isfinite(out) && out >= low && out <= high;
}

}  // namespace

std::string usage() {
    return R"(usage: ameotod [options]

ameotod synthesises rain from physics and streams it to JACK, or, where no JACK server
runs, to a WAV file (null backend). It is controlled over OSC (see docs/PROTOCOL.md).

Options:
  --port N            UDP port for OSC, 0..65535 (default 7770; 0 picks a free port)
  --tcp-port N        also serve OSC over TCP on port N, 0..65535 (default: off; 0
                      picks a free port). OSC 1.0 stream framing: each packet is
                      preceded by its size as a big-endian int32; replies come back
                      on the same connection. At most 16 connections, 64 KiB a packet
  --bind ADDRESS      IP address to listen on, UDP and TCP (default 127.0.0.1;
                      anything else is reachable from other machines and is logged)
  --allow CIDR,...    answer only senders in these networks, IPv4 or IPv6, e.g.
                      127.0.0.1/32,10.0.0.0/8,::1/128 (a bare address is one host);
                      datagrams (and TCP connections) from anyone
                      else are dropped without a reply and
                      counted in the log (default: every sender that reaches --bind)
  --backend KIND      auto | jack | null (default auto: JACK when a server runs,
                      otherwise null)
  --jack-name NAME    JACK client name (default ameoto); ports NAME:out_1..N
  --autoconnect       connect the JACK ports to the system playback ports
  --output FILE.wav   null backend: write the stream here, '-' for none
                      (default: ameoto-YYYYMMDD-HHMMSS.wav in the current folder)
  --rate HZ           null backend sample rate, 8000..384000 Hz (default 48000)
  --block FRAMES      null backend block size, 16..8192 frames (default 256)
  --realtime          null backend: pace to the clock (default unless --duration)
  --offline           null backend: render as fast as possible (default with --duration)
  --realtime-priority N
                      null backend, paced: the render thread's SCHED_FIFO priority,
                      1..99, or 0 for normal scheduling (default 70, as JACK's
                      clients; needs root or an rtprio limit, else it runs normally
                      and says so)
  --duration SECONDS  stop after this many seconds of audio (> 0)
  --seed N            random seed, 0..2^64-1 (default 0): same seed and same timed
                      events give the same samples
  --channels N        output channels, 1..16 (default 2): stereo for 2, else ring:N
  --format F          what the channels carry (docs/output-formats.md): stereo (default),
                      ears (two points 0.18 m apart), ring:N (N = 1..16 speakers on a
                      ring), ambix:ORDER (Ambisonics, ORDER 1..3: 4, 9 or 16 channels,
                      ACN order, SN3D, no Condon-Shortley phase; /listener/orientation
                      turns it), binaural (headphones: the ambix:3 bus decoded to two
                      ears through measured HRIRs, --hrtf; ports out_1, out_2 named
                      "left ear", "right ear"; /listener/orientation turns the head).
                      Default: the scene file's 'output format=', else stereo. JACK
                      ports stay out_1..out_N with pretty names ("ACN 0 W", ...)
  --hrtf FILE.sofa    binaural: the head-related impulse responses (AES69 SOFA, two
                      ears; default /usr/share/libmysofa/default.sofa, MIT KEMAR). The
                      decoder is built at start for the backend's block size (JACK's
                      buffer size, the null backend's --block), and again off the audio
                      thread when JACK's buffer size changes (docs/binaural.md)
  --scene NAME|FILE.scene
                      scene to start with: umbrella (default: light rain, 2 mm/h, on
                      an 8-panel nylon umbrella of 0.5 m radius), pond, tin-roof,
                      forest, street, NAME.scene in the scene folder, or a scene file
                      anywhere by its path (ending in .scene, relative to the current
                      folder; format in docs/scenes.md). A file that cannot be read or
                      parsed stops ameotod with exit status 1 and its file, line and
                      key. Over OSC, /scene/load takes names only
  --scene-dir DIR     the scene folder for /scene/load and /scene/save (default
                      $XDG_DATA_HOME/ameoto/scenes, else ~/.local/share/ameoto/scenes)
  --node K            play node K's part of the scene, 1..16: only the surfaces the
                      scene file gives node K (node=K; default node 1), with the same
                      listener and rain (give every node the same --seed): the nodes'
                      outputs sum to the whole scene (default: the whole scene)
  --start-at UNIX_SECONDS
                      JACK backend: play silence, and hold the rain, until this wall
                      time (seconds since 1970, UTC, e.g. $(date +%s) + 3), then start
                      on the JACK cycle nearest it: nodes given the same instant begin
                      their rain at the same frame (docs/nodes.md). Must be ahead of
                      now, at most one day
  --peers osc.udp://HOST:PORT,...
                      conduct these other nodes (HOST an IP address; at most 15): every
                      command this node accepts that changes the sound is sent on to
                      them, timed --peer-latency ahead, and applied here at the same
                      sample; each is asked for /status every 250 ms, one silent for
                      1.5 s is reported (/notice peers), and one that answers again is
                      sent the current rain, wind and listener; /nodes answers for all
  --peer-latency MS   how far ahead conducted commands are timed, 1..2000 ms (default
                      25: about 5 periods of 256 frames at 48 kHz)
  --rain MM/H         starting rain rate, 0..500 mm/h (default: the scene's; 0 for a
                      dry start where only /drop sounds)
  --fixed-detail      never shed detail because of the measured load: the stream then
                      depends only on the seed and the commands, sample for sample as
                      an offline render (by default a live stream sheds detail before
                      it would miss a deadline; /lod sets the budget)
  --record-score FILE
                      write the take to FILE as it plays: every command the engine
                      applied, at its sample, with the scene, seed, rate, output format
                      and level it started from (scsynth's binary score format, written
                      every 0.1 s, so it reads back after a crash); `ameoto render score
                      FILE` renders it again (sample for sample with --fixed-detail;
                      else at the full detail the live stream may have shed)
  --block-trace FILE  write every slow (or late-started) audio callback to FILE, a line
                      each: its wall and thread CPU time, faults, preemptions, what it did
                      (lattice drops, templates, commands), and whether the time was
                      ours (CPU) or the machine's (wall only); see docs/bench.md. Costs
                      four system calls a callback (about 9 us here) while on
  --block-trace-threshold PERCENT
                      slow means over this % of the period, 1..10000 (default 50)
  --level auto|physical
                      auto (default): when a scene is loaded, its level gain is chosen
                      (by rendering 3 s of its default rain off the audio thread and
                      measuring it, EBU R 128) so that rain plays at --loudness (through
                      the limiter when it is on, at most 12 dB more); once per load,
                      not an automatic gain control: heavier rain stays louder.
                      physical: 1.0 = 100 Pa at the listener, no level gain
  --loudness LUFS     auto's target for each scene's default rain, -60..-5 LUFS
                      integrated (default -23, EBU R 128); over OSC /loudness
  --gain DB           listening gain on top of the level, -80..80 dB (default: the
                      scene's 'output gain=', else 0); over OSC /gain, ramped over 50 ms
  --limiter on|off    look-ahead limiter before the output: ceiling -1 dBFS (sample
                      peak), look-ahead and attack 2 ms, release 100 ms, all channels
                      linked (default: on with --level auto, off with --level physical)
  --help              this text
  --version           the version

Signals: SIGINT and SIGTERM stop cleanly (the WAV is finalised); SIGHUP closes the WAV
and continues in a new file (never overwriting one that is still there).
Memory: every thread allocates from one heap (glibc's M_ARENA_MAX 1) and without
glibc's per-thread cache (ameotod starts itself again at once with
GLIBC_TUNABLES=glibc.malloc.tcache_count=0 added), so RSS follows what the server
holds across scene loads; MALLOC_ARENA_MAX, or GLIBC_TUNABLES naming arena_max or
tcache_count, in the environment overrides either.
Calibration: the engine's samples are physical: 1.0 = 100 Pa at the listener, so with
no gain 0 dBFS = 133.98 dB SPL (20 log10(100 Pa / 20 uPa)); a level gain and a gain of
G dB in all make 0 dBFS = 133.98 - G dB SPL. /status.reply field 15 and the log say the
figure in effect; the WAV's comment (LIST/INFO ICMT) says it for the file.
Units: rain rate mm/h, drop diameter mm, speeds m/s, positions m, gain dB, loudness LUFS.
)";
}

ParsedOptions parse_options(int argc, const char* const* argv) {
    ParsedOptions parsed;
    DaemonOptions& o = parsed.options;
    auto fail = [&](const std::string& message) {
        parsed.error = message;
        return parsed;
    };
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&](std::string& out) {
            if (i + 1 >= argc) return false;
            out = argv[++i];
            return true;
        };
        std::string v;
        long long n = 0;
        double d = 0.0;
        if (arg == "--help" || arg == "-h") {
            parsed.show_help = true;
        } else if (arg == "--version") {
            parsed.show_version = true;
        } else if (arg == "--fixed-detail") {
            o.fixed_detail = true;
        } else if (arg == "--autoconnect") {
            o.autoconnect = true;
        } else if (arg == "--realtime") {
            o.realtime = true;
        } else if (arg == "--offline") {
            o.realtime = false;
        } else if (arg == "--node") {
            if (!value(v) || !parse_int(v, 1, max_scene_nodes, n)) return fail("--node needs a node number 1..16");
            o.node = static_cast<int>(n);
        } else if (arg == "--start-at") {
            timespec now{};
            clock_gettime(CLOCK_REALTIME, &now);
            const double now_s = static_cast<double>(now.tv_sec) + now.tv_nsec * 1e-9;
            if (!value(v) || !parse_double(v, 0, 1e11, d)) return fail("--start-at needs a wall time in seconds since 1970");
            if (d <= now_s || d > now_s + 86400.0)
                return fail("--start-at: " + v + " is not ahead of now (" + std::to_string(static_cast<long long>(now_s)) +
                            " s since 1970) by at most a day");
            o.start_at_unix_ns = static_cast<std::int64_t>(std::llround(d * 1e9));
        } else if (arg == "--peers") {
            if (!value(v)) return fail("--peers needs osc.udp://HOST:PORT,...");
            std::string error;
            const auto peers = parse_peers(v, error);
            if (!peers) return fail("--peers: " + error);
            o.peers = *peers;
        } else if (arg == "--peer-latency") {
            if (!value(v) || !parse_double(v, 1, 2000, d)) return fail("--peer-latency needs 1..2000 ms");
            o.peer_latency_s = d * 1e-3;
        } else if (arg == "--realtime-priority") {
            if (!value(v) || !parse_int(v, 0, 99, n))
                return fail("--realtime-priority needs a priority 1..99, or 0 for normal scheduling");
            o.realtime_priority = static_cast<int>(n);
        } else if (arg == "--port") {
            if (!value(v) || !parse_int(v, 0, 65535, n)) return fail("--port needs a port number 0..65535");
            o.port = static_cast<int>(n);
        } else if (arg == "--tcp-port") {
            if (!value(v) || !parse_int(v, 0, 65535, n)) return fail("--tcp-port needs a port number 0..65535");
            o.tcp_port = static_cast<int>(n);
        } else if (arg == "--bind") {
            boost::system::error_code ec;
            if (!value(v)) return fail("--bind needs an IP address");
            boost::asio::ip::make_address(v, ec);
            if (ec) return fail("--bind: '" + v + "' is not an IP address");
            o.bind = v;
        } else if (arg == "--allow") {
            if (!value(v)) return fail("--allow needs networks in CIDR notation, e.g. 10.0.0.0/8,::1/128");
            std::string error;
            auto filter = SenderFilter::parse(v, error);
            if (!filter) return fail("--allow: " + error);
            o.allow = *filter;
        } else if (arg == "--backend") {
            if (!value(v)) return fail("--backend needs auto, jack or null");
            if (v == "auto") o.backend = BackendChoice::automatic;
            else if (v == "jack") o.backend = BackendChoice::jack;
            else if (v == "null") o.backend = BackendChoice::null;
            else return fail("--backend: '" + v + "' is not auto, jack or null");
        } else if (arg == "--jack-name") {
            if (!value(v) || v.empty() || v.size() > 63 || v.find(':') != std::string::npos)
                return fail("--jack-name needs a name of 1..63 characters without ':'");
            o.jack_name = v;
        } else if (arg == "--output") {
            if (!value(v) || v.empty()) return fail("--output needs a file name or '-'");
            o.output = v;
        } else if (arg == "--rate") {
            if (!value(v) || !parse_double(v, 8000, 384000, d)) return fail("--rate needs a sample rate 8000..384000 Hz");
            o.sample_rate = d;
        } else if (arg == "--block") {
            if (!value(v) || !parse_int(v, 16, 8192, n)) return fail("--block needs 16..8192 frames");
            o.block_size = static_cast<int>(n);
        } else if (arg == "--duration") {
            if (!value(v) || !parse_double(v, 1e-6, 1e7, d)) return fail("--duration needs a number of seconds > 0");
            o.duration_s = d;
        } else if (arg == "--seed") {
            unsigned long long s = 0;
            if (!value(v)) return fail("--seed needs a number 0..2^64-1");
            const auto r = std::from_chars(v.data(), v.data() + v.size(), s);
            if (r.ec != std::errc() || r.ptr != v.data() + v.size()) return fail("--seed needs a number 0..2^64-1");
            o.seed = s;
        } else if (arg == "--channels") {
            if (!value(v) || !parse_int(v, 1, 16, n)) return fail("--channels needs 1..16");
            o.channels = static_cast<int>(n);
            o.channels_given = true;
            if (o.format) return fail("give --format or --channels, not both (ring:N is N channels)");
        } else if (arg == "--format") {
            std::string error;
            if (!value(v)) return fail("--format needs stereo, ears, ring:N, ambix:ORDER or binaural");
            const auto f = parse_output_format(v, error);
            if (!f) return fail("--format: " + error);
            if (o.channels_given) return fail("give --format or --channels, not both (ring:N is N channels)");
            o.format = *f;
            o.channels = f->channels;
        } else if (arg == "--hrtf") {
            if (!value(v) || v.empty()) return fail("--hrtf needs a SOFA file");
            o.hrtf = v;
        } else if (arg == "--rain") {
            if (!value(v) || !parse_double(v, 0, 500, d)) return fail("--rain needs a rain rate 0..500 mm/h");
            o.rain_mm_per_h = d;
        } else if (arg == "--scene") {
            // The command line is trusted: a path is taken as given (over OSC, names only).
            if (!value(v)) return fail("--scene needs a scene name or a .scene file");
            if (!is_scene_name(v) && !v.ends_with(".scene"))
                return fail("--scene: '" + v + "' is neither a scene name (1-32 of A-Z a-z 0-9 - _) nor a file ending in .scene");
            o.scene = v;
        } else if (arg == "--record-score") {
            if (!value(v) || v.empty()) return fail("--record-score needs a file name");
            o.record_score = v;
        } else if (arg == "--block-trace") {
            if (!value(v) || v.empty()) return fail("--block-trace needs a file name");
            o.block_trace = v;
        } else if (arg == "--block-trace-threshold") {
            if (!value(v) || !parse_double(v, 1, 10000, d)) return fail("--block-trace-threshold needs 1..10000 (% of the period)");
            o.block_trace_threshold = d / 100.0;
        } else if (arg == "--level") {
            if (!value(v) || (v != "auto" && v != "physical")) return fail("--level needs auto or physical");
            o.level_auto = v == "auto";
        } else if (arg == "--loudness") {
            if (!value(v) || !parse_double(v, -60, -5, d)) return fail("--loudness needs a target of -60..-5 LUFS");
            o.target_lufs = d;
        } else if (arg == "--gain") {
            if (!value(v) || !parse_double(v, -80, 80, d)) return fail("--gain needs a gain of -80..80 dB");
            o.gain_db = d;
        } else if (arg == "--limiter") {
            if (!value(v) || (v != "on" && v != "off")) return fail("--limiter needs on or off");
            o.limiter = v == "on";
        } else if (arg == "--scene-dir") {
            if (!value(v) || v.empty()) return fail("--scene-dir needs a folder");
            o.scene_folder = v;
        } else {
            return fail("unknown option '" + arg + "' (see --help)");
        }
    }
    if (o.start_at_unix_ns && o.backend != BackendChoice::jack) return fail("--start-at needs --backend jack");
    return parsed;
}

}  // namespace ameoto
