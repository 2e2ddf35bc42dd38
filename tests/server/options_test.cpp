// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/options.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <ctime>
#include <string>
#include <vector>

namespace {
ameoto::ParsedOptions parse(std::vector<const char*> args) {
    args.insert(args.begin(), "ameotod");
    return ameoto::parse_options(static_cast<int>(args.size()), args.data());
}
}  // namespace

TEST_CASE("defaults follow the issue and the protocol core") {
    const auto p = parse({});
    CHECK(p.error.empty());
    CHECK(p.options.port == 7770);
    CHECK(p.options.bind == "127.0.0.1");
    CHECK(p.options.backend == ameoto::BackendChoice::automatic);
    CHECK(p.options.jack_name == "ameoto");
    CHECK(p.options.channels == 2);
    CHECK(p.options.scene == "umbrella");
    CHECK_FALSE(p.options.fixed_detail);
    CHECK_FALSE(p.options.tcp_port.has_value());   // OSC over TCP is off unless asked for
}

TEST_CASE("--tcp-port turns OSC over TCP on; 0 picks a free port") {
    CHECK(parse({"--tcp-port", "9001"}).options.tcp_port == std::optional<int>(9001));
    CHECK(parse({"--tcp-port", "0"}).options.tcp_port == std::optional<int>(0));
    for (const auto& args : std::vector<std::vector<const char*>>{{"--tcp-port"}, {"--tcp-port", "65536"}, {"--tcp-port", "-1"}, {"--tcp-port", "x"}}) {
        const auto p = parse(args);
        CHECK(p.error.find("--tcp-port") != std::string::npos);
    }
    CHECK(ameoto::usage().find("--tcp-port") != std::string::npos);
}

TEST_CASE("every option parses its valid values") {
    const auto p = parse({"--port", "9000", "--bind", "::1", "--backend", "null", "--jack-name", "rain", "--autoconnect",
                          "--output", "x.wav", "--rate", "96000", "--block", "64", "--realtime", "--duration", "2.5",
                          "--seed", "18446744073709551615", "--channels", "6", "--scene", "street", "--rain", "0",
                          "--scene-dir", "/tmp/scenes", "--fixed-detail"});
    REQUIRE(p.error.empty());
    CHECK(p.options.scene == "street");
    CHECK(p.options.scene_folder == std::optional<std::string>("/tmp/scenes"));
    CHECK(p.options.fixed_detail);
    CHECK(p.options.port == 9000);
    CHECK(p.options.bind == "::1");
    CHECK(p.options.backend == ameoto::BackendChoice::null);
    CHECK(p.options.autoconnect);
    CHECK(*p.options.output == "x.wav");
    CHECK(p.options.sample_rate == 96000.0);
    CHECK(p.options.block_size == 64);
    CHECK(*p.options.realtime);
    CHECK(*p.options.duration_s == 2.5);
    CHECK(p.options.seed == 18446744073709551615ULL);
    CHECK(p.options.channels == 6);
    CHECK(*p.options.rain_mm_per_h == 0.0);
}

TEST_CASE("bad values are refused with a message naming the option") {
    const std::vector<std::vector<const char*>> bad = {
        {"--port", "70000"}, {"--port", "12x"}, {"--port"}, {"--bind", "localhost.example"}, {"--backend", "alsa"},
        {"--jack-name", "a:b"}, {"--rate", "100"}, {"--rate", "nan"}, {"--block", "8"}, {"--duration", "0"},
        {"--duration", "-1"}, {"--seed", "-3"}, {"--channels", "0"}, {"--channels", "17"}, {"--scene", "../etc"}, {"--rain", "501"}, {"--rain", "-0.5"},
        {"--realtime-priority", "-1"}, {"--realtime-priority", "100"}, {"--realtime-priority", "x"}, {"--realtime-priority"},
        {"--frobnicate"}};
    for (const auto& args : bad) {
        const auto p = parse(args);
        INFO(args[0]);
        CHECK_FALSE(p.error.empty());
        CHECK(p.error.find(args[0]) != std::string::npos);
    }
}

TEST_CASE("--realtime-priority takes 0..99 (0: normal scheduling); 70 by default") {
    CHECK(parse({}).options.realtime_priority == 70);
    CHECK(parse({"--realtime-priority", "0"}).options.realtime_priority == 0);
    CHECK(parse({"--realtime-priority", "99"}).options.realtime_priority == 99);
    CHECK(ameoto::usage().find("--realtime-priority") != std::string::npos);
}

TEST_CASE("--help names the units") {
    const std::string u = ameoto::usage();
    for (const char* needle : {"mm/h", "Hz", "frames", "seconds", "--bind", "SIGHUP"}) CHECK(u.find(needle) != std::string::npos);
}

TEST_CASE("--allow takes IPv4 and IPv6 networks and refuses anything else, naming the option") {
    CHECK_FALSE(parse({}).options.allow.restricts());
    const auto p = parse({"--allow", "127.0.0.1/32,10.0.0.0/8,::1/128"});
    REQUIRE(p.error.empty());
    CHECK(p.options.allow.text() == "127.0.0.1/32,10.0.0.0/8,::1/128");
    CHECK(p.options.allow.allows(boost::asio::ip::make_address("10.9.8.7")));
    CHECK_FALSE(p.options.allow.allows(boost::asio::ip::make_address("192.0.2.1")));
    for (const char* bad : {"10.0.0.0/40", "10.0.0.1/8", "localhost", "10.0.0.0/8,"}) {
        const auto r = parse({"--allow", bad});
        CHECK_MESSAGE(r.error.find("--allow: ") == 0, bad << ": " << r.error);
    }
    CHECK(parse({"--allow"}).error.find("--allow needs") == 0);
    CHECK(ameoto::usage().find("--allow CIDR") != std::string::npos);
}

TEST_CASE("--block-trace names a file and its threshold in % of the period; off by default") {
    CHECK_FALSE(parse({}).options.block_trace.has_value());
    CHECK(parse({}).options.block_trace_threshold == ameoto::test::relative(0.5));
    const auto p = parse({"--block-trace", "/tmp/blocks.trace", "--block-trace-threshold", "80"});
    REQUIRE(p.error.empty());
    CHECK(p.options.block_trace == std::optional<std::string>("/tmp/blocks.trace"));
    CHECK(p.options.block_trace_threshold == ameoto::test::relative(0.8));
    CHECK(parse({"--block-trace"}).error.find("--block-trace") != std::string::npos);
    CHECK(parse({"--block-trace-threshold", "0"}).error.find("--block-trace-threshold") != std::string::npos);
    CHECK(ameoto::usage().find("--block-trace FILE") != std::string::npos);
}

TEST_CASE("--help names the heap policy and the environment that overrides it (server/memory_return.hpp)") {
    const std::string u = ameoto::usage();
    CHECK(u.find("one heap") != std::string::npos);
    CHECK(u.find("MALLOC_ARENA_MAX") != std::string::npos);
}

TEST_CASE("--scene takes a name or a scene file's path (the command line is trusted); anything else is refused") {
    CHECK(parse({"--scene", "my-rain"}).options.scene == "my-rain");            // the folder's, or built in
    CHECK(parse({"--scene", "my.scene"}).options.scene == "my.scene");          // a file, relative to the current folder
    CHECK(parse({"--scene", "../rain/my.scene"}).options.scene == "../rain/my.scene");
    CHECK(parse({"--scene", "/srv/rain/x.scene"}).error.empty());
    for (const char* bad : {"../etc", "/tmp/x", "my.scene.txt", ""}) {
        const auto p = parse({"--scene", bad});
        INFO(bad);
        CHECK(p.error.find("--scene: '" + std::string(bad) + "' is neither a scene name") == 0);
    }
    CHECK(ameoto::usage().find("--scene NAME|FILE.scene") != std::string::npos);
}

TEST_CASE("--level, --loudness, --gain, --limiter: defaults, valid values, refusals with the range") {
    const auto d = parse({});
    CHECK(d.options.level_auto);                 // issue 21: auto is ameotod's default
    CHECK(d.options.target_lufs == -23.0);       // EBU R 128
    CHECK_FALSE(d.options.gain_db.has_value());  // the scene's
    CHECK(d.options.limiter_on());               // on with auto...
    CHECK_FALSE(parse({"--level", "physical"}).options.limiter_on());   // ...off with physical
    CHECK(parse({"--level", "physical", "--limiter", "on"}).options.limiter_on());
    CHECK_FALSE(parse({"--limiter", "off"}).options.limiter_on());
    const auto p = parse({"--loudness", "-18", "--gain", "-6.5"});
    CHECK(p.error.empty());
    CHECK(p.options.target_lufs == -18.0);
    CHECK(p.options.gain_db == std::optional<double>(-6.5));
    CHECK(parse({"--level", "loud"}).error == "--level needs auto or physical");
    CHECK(parse({"--loudness", "-3"}).error == "--loudness needs a target of -60..-5 LUFS");
    CHECK(parse({"--gain", "81"}).error == "--gain needs a gain of -80..80 dB");
    CHECK(parse({"--limiter", "yes"}).error == "--limiter needs on or off");
    CHECK(ameoto::usage().find("0 dBFS = 133.98 dB SPL") != std::string::npos);   // the calibration, stated
}

TEST_CASE("--node takes the scene's node 1..16 to play; the whole scene (0) by default") {
    CHECK(parse({}).options.node == 0);
    CHECK(parse({"--node", "1"}).options.node == 1);
    CHECK(parse({"--node", "16"}).options.node == 16);
    for (const auto& args : std::vector<std::vector<const char*>>{{"--node", "0"}, {"--node", "17"}, {"--node", "x"}, {"--node"}}) {
        const auto p = parse(args);
        CHECK(p.error == "--node needs a node number 1..16");
    }
    CHECK(ameoto::usage().find("--node K") != std::string::npos);
}

TEST_CASE("--start-at takes a wall time ahead of now, by at most a day, with the JACK backend only") {
    const std::string soon = std::to_string(static_cast<long long>(std::time(nullptr)) + 60);
    const auto p = parse({"--backend", "jack", "--start-at", soon.c_str()});
    REQUIRE(p.error.empty());
    REQUIRE(p.options.start_at_unix_ns.has_value());
    CHECK(*p.options.start_at_unix_ns == std::stoll(soon) * 1'000'000'000LL);
    CHECK_FALSE(parse({}).options.start_at_unix_ns.has_value());
    CHECK(parse({"--start-at", soon.c_str()}).error == "--start-at needs --backend jack");
    CHECK(parse({"--backend", "jack", "--start-at", "1000"}).error.find("is not ahead of now") != std::string::npos);
    const std::string far = std::to_string(static_cast<long long>(std::time(nullptr)) + 2 * 86400);
    CHECK(parse({"--backend", "jack", "--start-at", far.c_str()}).error.find("by at most a day") != std::string::npos);
    CHECK(parse({"--backend", "jack", "--start-at", "soon"}).error == "--start-at needs a wall time in seconds since 1970");
    CHECK(ameoto::usage().find("--start-at UNIX_SECONDS") != std::string::npos);
}

TEST_CASE("--peers takes osc.udp://IP:PORT addresses; --peer-latency 1..2000 ms, 25 by default") {
    const auto p = parse({"--peers", "osc.udp://127.0.0.1:7771/,osc.udp://[::1]:7772"});
    REQUIRE(p.error.empty());
    REQUIRE(p.options.peers.size() == 2);
    CHECK(p.options.peers[0].port() == 7771);
    CHECK(p.options.peers[1].address().is_v6());
    CHECK(parse({}).options.peers.empty());
    CHECK(parse({}).options.peer_latency_s == ameoto::test::relative(0.025));
    CHECK(parse({"--peer-latency", "40"}).options.peer_latency_s == ameoto::test::relative(0.040));
    CHECK(parse({"--peer-latency", "0"}).error == "--peer-latency needs 1..2000 ms");
    CHECK(parse({"--peers", "127.0.0.1:7771"}).error == "--peers: '127.0.0.1:7771' is not osc.udp://HOST:PORT");
    CHECK(parse({"--peers", "osc.udp://host.example:7771"}).error == "--peers: 'host.example' is not an IP address");
    CHECK(parse({"--peers", "osc.udp://127.0.0.1:0"}).error == "--peers: '0' is not a port 1..65535");
    CHECK(parse({"--peers", "osc.udp://127.0.0.1"}).error == "--peers: '127.0.0.1' has no HOST:PORT");
    CHECK(ameoto::usage().find("--peers osc.udp://HOST:PORT") != std::string::npos);
}

TEST_CASE("--format: every output format, its channels, and --channels not beside it") {
    const auto a = parse({"--format", "ambix:3"});
    REQUIRE(a.error.empty());
    REQUIRE(a.options.format);
    CHECK(a.options.format->name() == "ambix:3");
    CHECK(a.options.channels == 16);
    CHECK(parse({"--format", "ring:6"}).options.channels == 6);
    CHECK(parse({"--format", "ears"}).options.format->kind == ameoto::OutputKind::ears);
    {
        const auto b = parse({"--format", "binaural"});   // two ears of the ambix:3 bus (the renderer's 16 channels)
        REQUIRE(b.error.empty());
        CHECK(b.options.channels == 2);
        CHECK(b.options.hrtf == "/usr/share/libmysofa/default.sofa");
        CHECK(parse({"--format", "binaural", "--hrtf", "/x/y.sofa"}).options.hrtf == "/x/y.sofa");
        CHECK(parse({"--hrtf"}).error == "--hrtf needs a SOFA file");
        CHECK(parse({"--hrtf", ""}).error == "--hrtf needs a SOFA file");
        CHECK(ameoto::usage().find("--hrtf FILE.sofa") != std::string::npos);
    }
    CHECK(parse({"--format", "ambix:4"}).error == "--format: 'ambix:4': the Ambisonic order is 1, 2 or 3 (ambix:ORDER: 4, 9 or 16 channels)");
    CHECK(parse({"--format", "quad"}).error.find("is not an output format") != std::string::npos);
    CHECK(parse({"--format", "ambix:1", "--channels", "4"}).error == "give --format or --channels, not both (ring:N is N channels)");
    CHECK(parse({"--channels", "4", "--format", "ambix:1"}).error == "give --format or --channels, not both (ring:N is N channels)");
    CHECK(ameoto::usage().find("--format F") != std::string::npos);
}
