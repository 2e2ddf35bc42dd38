// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod end to end: the real daemon, real OSC datagrams over loopback, real WAV files.

#include <doctest/doctest.h>
#include <signal.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "tests/support/child_process.hpp"
#include "tests/support/audio_clock.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"
#include "tests/support/program_paths.hpp"
#include "tests/support/rt_report.hpp"
#include "tests/support/timing_scale.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::test::ChildProcess;
using ameoto::test::OscTestClient;
// ameotod ARGS --port 0, listening and running (10 s for each), stopped when it goes out of scope.
using Daemon = ameoto::test::DaemonProcess;

namespace {

using ameoto::test::ameotod;

}  // namespace

TEST_CASE("a /drop over UDP sounds within a block, with silence before it") {
    const std::string wav = ameoto::test::temp_path("drop.wav");
    const std::string report = ameoto::test::temp_path("drop-rt.txt");
    long long before_frame = 0, after_frame = 0;
    {
        // A dry start (--rain 0), paced to the clock, with the real-time probe preloaded.
        Daemon d({"--backend", "null", "--output", wav, "--realtime", "--rain", "0", "--block", "256"},
                 {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report});
        OscTestClient client(d.port());
        std::this_thread::sleep_for(300ms);
        before_frame = ameoto::test::audio_frames(client);
        client.send("/drop", {OscArgument::from_float(4.0f), OscArgument::from_float(0.0f), OscArgument::from_float(0.2f),
                              OscArgument::from_float(0.05f)});
        REQUIRE(client.request("/sync", {OscArgument::from_int(7)}, "/synced", 2s));
        after_frame = ameoto::test::audio_frames(client);
        std::this_thread::sleep_for(300ms);
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    const auto w = ameoto::test::read_wav(wav);
    REQUIRE_MESSAGE(w.ok, w.error);
    const long long onset = w.first_nonzero_frame();
    INFO("status before " << before_frame << ", onset " << onset << ", status after " << after_frame);
    REQUIRE(onset >= 0);
    // Silence before: every sample before the onset is exactly zero (no rain, nothing else).
    // The drop was sent after the first status and sounds no later than the block that applied the
    // /sync sent right behind it: the renderer applies untimed commands at the next block's first sample.
    CHECK(onset >= before_frame);
    CHECK(onset <= after_frame);
    // Latency bound on a shared machine: two blocks plus 30 ms of scheduling slack.
    CHECK(onset - before_frame <= 2 * 256 + static_cast<long long>(0.030 * 48000));
    // The real-time probe ran in every block and saw nothing forbidden.
    const auto rt = ameoto::test::read_rt_report(report);
    INFO(rt.text);
    CHECK(rt.no_violations());
    CHECK(rt.probed());
}

TEST_CASE("a timetagged bundle plays its /drop at the bundle's time; a late bundle plays at once and is counted") {
    using ameoto::protocol::Timetag;
    const std::string wav = ameoto::test::temp_path("bundle.wav");
    long long before_frame = 0;
    double sent_at = 0.0;
    std::int64_t late = -1;
    {
        Daemon d({"--backend", "null", "--output", wav, "--realtime", "--rain", "0"});
        OscTestClient client(d.port());
        std::this_thread::sleep_for(300ms);
        auto wall = [] {
            timespec t{};
            clock_gettime(CLOCK_REALTIME, &t);
            return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
        };
        const auto drop = ameoto::protocol::encode_message(
            "/drop", {OscArgument::from_float(4.0f), OscArgument::from_float(0.0f), OscArgument::from_float(0.2f), OscArgument::from_float(0.0f)});
        before_frame = ameoto::test::audio_frames(client);
        sent_at = wall();
        // 400 ms ahead: the server must hold it and play it then, not now.
        client.send_raw(ameoto::protocol::encode_bundle(Timetag::from_unix_seconds(sent_at + 0.4), {drop}));
        std::this_thread::sleep_for(800ms);
        // One second in the past: played at once, and /status counts it as late.
        client.send_raw(ameoto::protocol::encode_bundle(Timetag::from_unix_seconds(wall() - 1.0), {drop}));
        REQUIRE(client.request("/sync", {OscArgument::from_int(1)}, "/synced", 2s));
        const auto status = client.request("/status", {}, "/status.reply", 2s);
        REQUIRE(status);
        late = status->args[7].integer;
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    CHECK(late == 1);
    const auto w = ameoto::test::read_wav(wav);
    REQUIRE(w.ok);
    const long long onset = w.first_nonzero_frame();
    // The status before the send says which frame was current then (to within a block); the drop must
    // sound 400 ms (19200 frames) later, give or take two blocks and the scheduling slack of a shared
    // machine (30 ms). A drop played on arrival would sound about 19000 frames too early.
    const long long expected = before_frame + 19200;
    INFO("onset " << onset << ", expected about " << expected);
    CHECK(onset >= expected - 2 * 256 - 1440);
    CHECK(onset <= expected + 2 * 256 + 1440);
}

TEST_CASE("materials change live: /done once in use, refusals with the bound, no real-time violations") {
    const std::string report = ameoto::test::temp_path("materials-rt.txt");
    {
        // A material or liquid change rebuilds the impact templates (51 drop sizes through the full model)
        // on the worker: about 1 s of CPU on a quiet machine, several times that on a loaded CI machine.
        Daemon d({"--backend", "null", "--output", "-", "--realtime", "--rain", "30"},
                 {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report});
        OscTestClient client(d.port());
        auto s = [](const char* v) { return OscArgument::from_string(v); };
        auto f = [](double v) { return OscArgument::from_float(static_cast<float>(v)); };
        auto done = client.request("/material/surface", {s("umbrella"), s("vinyl")}, "/done", 20s);
        REQUIRE(done);
        CHECK(done->args[0].text == "/material/surface");
        // A custom material, stored under its name, then used again by name.
        REQUIRE(client.request("/material/surface", {s("umbrella"), s("rubber"), f(0.5), f(300), f(30), f(1e-5)}, "/done", 20s));
        REQUIRE(client.request("/material/surface", {s("umbrella"), s("rubber")}, "/done", 20s));
        // Too stiff to run live: refused with its bound, and the sound goes on.
        const auto refused = client.request("/material/surface", {s("umbrella"), s("seed-nylon")}, "/fail", 10s);
        REQUIRE(refused);
        CHECK(refused->args[1].text.find("sub-steps") != std::string::npos);
        CHECK(refused->args[1].text.find("omega_max T") != std::string::npos);
        REQUIRE(client.request("/material/liquid", {s("milk")}, "/done", 20s));
        REQUIRE(client.request("/material/liquid", {s("syrup"), f(1300), f(0.07), f(5)}, "/done", 20s));
        const auto bad = client.request("/material/liquid", {s("water"), f(1000), f(0.07), f(0.001)}, "/fail", 2s);
        REQUIRE(bad);
        CHECK(bad->args[1].text.find("preset") != std::string::npos);
        const auto status = client.request("/status", {}, "/status.reply", 2s);
        REQUIRE(status);
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    const auto rt = ameoto::test::read_rt_report(report);
    INFO(rt.text);
    CHECK(rt.no_violations());
    CHECK(rt.probed());
}

TEST_CASE("/drop plays the seed's full model: a lattice drop, counted in the full tier while it lives") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--rain", "0"});
    OscTestClient client(d.port());
    auto f = [](double v) { return OscArgument::from_float(static_cast<float>(v)); };
    client.send("/drop", {f(5.0), f(0.0), f(0.2), f(0.05)});
    REQUIRE(client.request("/sync", {OscArgument::from_int(3)}, "/synced", 2s));
    const auto status = client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(status);
    // Field 4: active drops in the full tier (its pieces fly off the cap and fall below it in about half
    // a second, then it retires); field 5: impulse-model impacts, none without rain.
    CHECK(status->args[3].integer == 1);
    CHECK(status->args[4].integer == 0);
    // A liquid change rebuilds the scene on the worker; the next drop is milk and is counted the same way.
    REQUIRE(client.request("/material/liquid", {OscArgument::from_string("milk")}, "/done", 20s));
    client.send("/drop", {f(3.0), f(0.0), f(-0.2), f(0.05)});
    REQUIRE(client.request("/sync", {OscArgument::from_int(4)}, "/synced", 2s));
    const auto after = client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(after);
    CHECK(after->args[3].integer >= 1);
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
}

TEST_CASE("scenes load and save over OSC: built-ins, the scene folder, refusals that change nothing") {
    const std::string report = ameoto::test::temp_path("scenes-rt.txt");
    const std::string folder = ameoto::test::temp_path("scene-folder");
    std::filesystem::create_directories(folder);
    std::ofstream(folder + "/broken.scene") << "ameoto-scene 1\nrain rate=900\n";
    {
        Daemon d({"--backend", "null", "--output", "-", "--realtime", "--scene", "pond", "--scene-dir", folder},
                 {"LD_PRELOAD=" AMEOTO_RT_INTERPOSER, "AMEOTO_RT_REPORT=" + report});
        OscTestClient client(d.port());
        auto s = [](const char* v) { return OscArgument::from_string(v); };
        auto f = [](double v) { return OscArgument::from_float(static_cast<float>(v)); };
        // The pond has no umbrella: /drop on it is refused.
        const auto no_umbrella = client.request("/drop", {f(3), f(0), f(0.2), f(0.0)}, "/fail", 2s);
        REQUIRE(no_umbrella);
        CHECK(no_umbrella->args[1].text.find("no surface named 'umbrella'") != std::string::npos);
        // Every built-in loads live.
        for (const char* name : {"street", "tin-roof", "forest", "umbrella"}) {
            CAPTURE(name);
            const auto done = client.request("/scene/load", {s(name)}, "/done", 10s);
            REQUIRE(done);
            CHECK(done->args[0].text == "/scene/load");
        }
        // With the umbrella back, /drop is accepted (no reply; the /sync behind it answers).
        client.send("/drop", {f(3), f(0), f(0.2), f(0.0)});
        REQUIRE(client.request("/sync", {OscArgument::from_int(9)}, "/synced", 2s));
        // Save what plays (with the rate changed over OSC), then load it back by name.
        client.send("/rain/rate", {f(17)});
        const auto saved = client.request("/scene/save", {s("my-rain")}, "/done", 5s);
        REQUIRE(saved);
        CHECK(saved->args[0].text == "/scene/save");
        std::ifstream in(folder + "/my-rain.scene");
        const std::string text((std::istreambuf_iterator<char>(in)), {});
        CHECK(text.find("rain rate=17") != std::string::npos);
        REQUIRE(client.request("/scene/load", {s("my-rain")}, "/done", 10s));
        // Refusals: a path, a built-in's name to save under, a broken file (with its line), a missing one.
        for (const char* bad : {"../etc", "/tmp/x", "a.scene"}) {
            const auto refused = client.request("/scene/load", {s(bad)}, "/fail", 2s);
            REQUIRE(refused);
            CHECK(refused->args[1].text.find("not a path") != std::string::npos);
        }
        const auto builtin = client.request("/scene/save", {s("pond")}, "/fail", 2s);
        REQUIRE(builtin);
        CHECK(builtin->args[1].text.find("built-in") != std::string::npos);
        const auto broken = client.request("/scene/load", {s("broken")}, "/fail", 5s);
        REQUIRE(broken);
        CHECK(broken->args[1].text.find("broken.scene:2: rate: 900 mm/h is outside 0..500") != std::string::npos);
        const auto missing = client.request("/scene/load", {s("nowhere")}, "/fail", 5s);
        REQUIRE(missing);
        CHECK(missing->args[1].text.find("no scene named 'nowhere'") != std::string::npos);
        // Editing the scene: surfaces, the drop size distribution, wind and the listener.
        auto added = client.request("/surface/add", {s("roof"), s("plate"), s("glass"), f(0.8), f(0.6), f(2), f(1), f(2.5)}, "/done", 10s);
        REQUIRE(added);
        CHECK(added->args[0].text == "/surface/add");
        const auto twice = client.request("/surface/add", {s("roof"), s("plate"), s("tin"), f(1), f(1), f(0), f(0), f(3)}, "/fail", 2s);
        REQUIRE(twice);
        CHECK(twice->args[1].text.find("already in the scene") != std::string::npos);
        const auto gold = client.request("/surface/set", {s("roof"), s("plate"), s("gold"), f(1), f(1), f(0), f(0), f(3)}, "/fail", 2s);
        REQUIRE(gold);
        CHECK(gold->args[1].text.find("material 'gold' is not one of tin, glass, car-roof") != std::string::npos);
        REQUIRE(client.request("/surface/set", {s("roof"), s("plate"), s("tin"), f(1), f(0.6), f(0), f(1), f(3)}, "/done", 10s));
        const auto dsd = client.request("/rain/dsd", {s("gamma"), f(2), f(3)}, "/done", 10s);
        REQUIRE(dsd);
        CHECK(dsd->args[0].text == "/rain/dsd");
        const auto hail = client.request("/rain/dsd", {s("hail")}, "/fail", 2s);
        REQUIRE(hail);
        client.send("/rain/wind", {f(6), f(90), f(0.3)});
        client.send("/listener", {f(1), f(0.5), f(1.6), f(30)});
        REQUIRE(client.request("/sync", {OscArgument::from_int(10)}, "/synced", 2s));
        REQUIRE(client.request("/surface/remove", {s("roof")}, "/done", 10s));
        const auto gone = client.request("/surface/remove", {s("roof")}, "/fail", 2s);
        REQUIRE(gone);
        REQUIRE(client.request("/scene/save", {s("edited")}, "/done", 5s));
        std::ifstream edited(folder + "/edited.scene");
        const std::string edited_text((std::istreambuf_iterator<char>(edited)), {});
        CHECK(edited_text.find("dsd=gamma mu=2 lambda=3 wind=6 direction=90 gust=0.3") != std::string::npos);
        CHECK(edited_text.find("listener x=1 y=0.5 z=1.6 facing=30") != std::string::npos);
        CHECK(edited_text.find("roof") == std::string::npos);
        // Still serving, still the saved scene's rate. Field 12 is the current rate, which ramps (1 s) from
        // the old scene's after each rebuild above (/rain/dsd, /surface/set, /surface/remove), so it is
        // read again until the ramp is over (a rebuild that comes sooner restarts the ramp: read once,
        // it gave 16.78 when the rebuilds came quickly).
        double rate = 0.0;
        for (int i = 0; i < 20 && std::abs(rate - 17.0) > 1e-5; ++i) {
            if (i > 0) std::this_thread::sleep_for(250ms);
            const auto status = client.request("/status", {}, "/status.reply", 2s);
            REQUIRE(status);
            rate = status->args[11].number;
        }
        CHECK(rate == doctest::Approx(17.0));
        CHECK(d.process().stop(SIGTERM, 5s) == 0);
    }
    const auto rt = ameoto::test::read_rt_report(report);
    INFO(rt.text);
    CHECK(rt.no_violations());
}

TEST_CASE("bad messages get /fail with a reason; the server keeps serving") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime"});
    OscTestClient client(d.port());
    struct Bad {
        std::vector<unsigned char> bytes;
        std::string address, reason;
    };
    const std::vector<Bad> bad = {
        {ameoto::protocol::encode_message("/no/such/thing", {}), "/no/such/thing", "unknown address"},
        {ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_string("heavy")}), "/rain/rate", "expected a number"},
        {ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(NAN)}), "/rain/rate", "not a finite number"},
        {ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(INFINITY)}), "/rain/rate", "not a finite number"},
        {ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(1e6f)}), "/rain/rate", "outside 0..500"},
        {ameoto::protocol::encode_message("/drop", {OscArgument::from_float(3)}), "/drop", "expected 4 to 5 arguments"},
        {{'/', 'x', 0, 0, ',', 'f', 0, 0}, "/x", "malformed"},
        {{1, 2, 3, 4}, "", "not an OSC message"},
    };
    for (const auto& b : bad) {
        client.send_raw(b.bytes);
        const auto reply = client.wait_for("/fail", 2s);
        REQUIRE(reply);
        REQUIRE(reply->types == "ss");
        CHECK(reply->args[0].text == b.address);
        CHECK(reply->args[1].text.find(b.reason) != std::string::npos);
    }
    // Nothing changed: the rain rate is still the scene's 2 mm/h, and the server answers.
    const auto status = client.request("/status", {}, "/status.reply", 2s);
    REQUIRE(status);
    CHECK(status->args[11].number == doctest::Approx(2.0));
    CHECK(status->args[12].text == "null");
    CHECK(status->args[8].number == 48000.0);
    // A good message after all that still works.
    client.send("/rain/rate", {OscArgument::from_int(30)});
    CHECK_FALSE(client.wait_for("/fail", 300ms));
    CHECK(d.process().running());
}

TEST_CASE("/quit answers /done and stops cleanly") {
    const std::string wav = ameoto::test::temp_path("quit.wav");
    Daemon d({"--backend", "null", "--output", wav, "--realtime"});
    OscTestClient client(d.port());
    const auto done = client.request("/quit", {}, "/done", 2s);
    REQUIRE(done);
    CHECK(done->args[0].text == "/quit");
    CHECK(d.process().wait(5s) == 0);
    CHECK(ameoto::test::read_wav(wav).ok);
}

TEST_CASE("SIGTERM leaves a WAV that reads back whole") {
    const std::string wav = ameoto::test::temp_path("sigterm.wav");
    Daemon d({"--backend", "null", "--output", wav, "--realtime", "--rain", "20"});
    OscTestClient client(d.port());
    // 1.1 s of audio by the audio clock (a wall-clock sleep gave 0.78 s under the sanitizers in CI).
    ameoto::test::wait_for_audio(client, 1.1);
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
    const auto line = d.process().wait_for_line("wrote ", 1s);
    REQUIRE(line);
    const long long reported = std::stoll(line->substr(line->find("wrote ") + 6));
    const auto w = ameoto::test::read_wav(wav);
    REQUIRE_MESSAGE(w.ok, w.error);
    CHECK(w.frames == reported);
    CHECK(w.frames > 48000);            // more than a second of audio
    CHECK(w.is_float);
    CHECK(w.channels == 2);
    double energy = 0.0;
    for (float s : w.samples) {
        REQUIRE(std::isfinite(s));
        energy += static_cast<double>(s) * s;
    }
    CHECK(energy > 0.0);                 // rain is audible
}

TEST_CASE("SIGHUP closes the WAV and continues in a new file; neither is overwritten") {
    const std::string wav = ameoto::test::temp_path("hup.wav");
    Daemon d({"--backend", "null", "--output", wav, "--realtime"});
    std::this_thread::sleep_for(300ms);
    d.process().signal(SIGHUP);
    REQUIRE(d.process().wait_for_line("SIGHUP", 2s));
    std::this_thread::sleep_for(300ms);
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
    const auto first = ameoto::test::read_wav(wav);
    const std::string second_path = wav.substr(0, wav.size() - 4) + "-1.wav";
    const auto second = ameoto::test::read_wav(second_path);
    REQUIRE(first.ok);
    REQUIRE(second.ok);
    CHECK(first.frames > 0);
    CHECK(second.frames > 0);
}

TEST_CASE("offline renders are exact in length and reproducible to the sample") {
    // 1.5 s of audio; 0.5 s under the sanitizers (three renders there cost 26 s at 1.5 s).
    const bool short_run = ameoto::test::sanitized_build();
    auto render = [&](const std::string& name, const std::string& seed) {
        const std::string wav = ameoto::test::temp_path(name);
        ChildProcess p({ameotod, "--backend", "null", "--duration", short_run ? "0.5" : "1.5", "--seed", seed, "--output", wav, "--port", "0",
                        "--rain", "10"});
        CHECK(p.wait(60s) == 0);
        return ameoto::test::read_wav(wav);
    };
    const auto a = render("seed1-a.wav", "1");
    const auto b = render("seed1-b.wav", "1");
    const auto c = render("seed2.wav", "2");
    REQUIRE(a.ok);
    CHECK(a.frames == (short_run ? 24000 : 72000));
    CHECK(a.samples == b.samples);
    CHECK(a.samples != c.samples);
}

TEST_CASE("start-up errors are clear and exit non-zero") {
    SUBCASE("a port in use") {
        Daemon first({"--backend", "null", "--output", "-", "--realtime"});
        ChildProcess second({ameotod, "--backend", "null", "--output", "-", "--port", std::to_string(first.port())});
        CHECK(second.wait(10s) == 1);
        CHECK(second.output().find("cannot listen") != std::string::npos);
    }
    SUBCASE("a bad option") {
        ChildProcess p({ameotod, "--rate", "12"});
        CHECK(p.wait(10s) == 2);
        CHECK(p.output().find("--rate") != std::string::npos);
    }
    SUBCASE("--backend jack without a JACK server") {
        ChildProcess p({ameotod, "--backend", "jack", "--port", "0"}, {"JACK_DEFAULT_SERVER=ameoto-no-such-server"});
        CHECK(p.wait(20s) == 1);
        CHECK(p.output().find("cannot use JACK") != std::string::npos);
    }
}
