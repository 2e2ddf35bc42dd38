// SPDX-License-Identifier: GPL-3.0-or-later
// Faults and who may talk (issue 8): --bind and --allow with real senders on loopback addresses, WAVs
// after SIGKILL, a disk that fills (a real tmpfs of a few hundred KiB), an output file removed while
// written, a scene save on a full disk, and a JACK server killed outright and started again.

#include <arpa/inet.h>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "tests/support/child_process.hpp"
#include "tests/support/audio_clock.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/jack_server.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/wav_file.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;
using Daemon = ameoto::test::DaemonProcess;
namespace fs = std::filesystem;

namespace {

// A UDP client whose datagrams come from a chosen loopback address (all of 127/8 is loopback on Linux;
// ::1 for IPv6), to play a sender inside or outside --allow. It sends to the same family's loopback.
class ClientFrom {
public:
    ClientFrom(const std::string& local_address, int server_port) : v6_(local_address.find(':') != std::string::npos) {
        fd_ = socket(v6_ ? AF_INET6 : AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        int bound = -1;
        if (v6_) {
            sockaddr_in6 local{};
            local.sin6_family = AF_INET6;
            inet_pton(AF_INET6, local_address.c_str(), &local.sin6_addr);
            bound = bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local);
            to6_.sin6_family = AF_INET6;
            to6_.sin6_port = htons(static_cast<std::uint16_t>(server_port));
            to6_.sin6_addr = in6addr_loopback;
        } else {
            sockaddr_in local{};
            local.sin_family = AF_INET;
            inet_pton(AF_INET, local_address.c_str(), &local.sin_addr);
            bound = bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local);
            to4_.sin_family = AF_INET;
            to4_.sin_port = htons(static_cast<std::uint16_t>(server_port));
            to4_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        }
        if (fd_ < 0 || bound != 0) throw std::runtime_error("cannot bind a client to " + local_address + ": " + std::strerror(errno));
    }
    ~ClientFrom() { close(fd_); }
    void send(const std::vector<unsigned char>& bytes) {
        if (v6_)
            sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to6_), sizeof to6_);
        else
            sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to4_), sizeof to4_);
    }
    // The next datagram's address, or "" when none comes in time.
    std::string receive_address(std::chrono::milliseconds timeout) {
        pollfd p{fd_, POLLIN, 0};
        if (poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return "";
        unsigned char buffer[65536];
        const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
        if (n <= 0) return "";
        const auto packet = ameoto::protocol::decode_packet(buffer, static_cast<std::size_t>(n));
        return packet.messages.empty() ? std::string("?") : packet.messages.front().address;
    }

private:
    bool v6_;
    int fd_ = -1;
    sockaddr_in to4_{};
    sockaddr_in6 to6_{};
};

std::optional<ameoto::protocol::DecodedMessage> wait_for_notice(OscTestClient& client, const std::string& containing,
                                                               std::chrono::milliseconds timeout) {
    auto matches = [&](const ameoto::protocol::DecodedMessage& m) {
        return m.address == "/notice" && m.args.size() == 2 && m.args[1].text.find(containing) != std::string::npos;
    };
    // One may have come in while the client waited for another reply.
    for (auto it = client.others.begin(); it != client.others.end(); ++it)
        if (matches(*it)) {
            auto m = *it;
            client.others.erase(it);
            return m;
        }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        auto m = client.wait_for("/notice", left);
        if (!m) return std::nullopt;
        if (matches(*m)) return m;
    }
    return std::nullopt;
}

// A tmpfs of SIZE mounted on a fresh folder for one test (root only); unmounted at the end.
class SmallDisk {
public:
    explicit SmallDisk(const std::string& size) : dir_("ameoto-small-disk") {
        mounted_ = ::mount("tmpfs", dir_.path().c_str(), "tmpfs", MS_NOSUID | MS_NODEV, ("size=" + size).c_str()) == 0;
        if (!mounted_) why_ = std::strerror(errno);
    }
    ~SmallDisk() {
        if (mounted_) ::umount2(dir_.path().c_str(), MNT_DETACH);
    }
    bool mounted() const { return mounted_; }
    bool grow(const std::string& size) const {
        return ::mount(nullptr, dir_.path().c_str(), nullptr, MS_REMOUNT | MS_NOSUID | MS_NODEV, ("size=" + size).c_str()) == 0;
    }
    const std::string& why() const { return why_; }
    fs::path path() const { return dir_.path(); }
    // Writes a filler file until the disk refuses (ENOSPC); returns the errno that stopped it.
    int fill() const {
        const int fd = ::open((dir_.path() / "filler").c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
        std::vector<char> block(4096, 'x');
        int error = 0;
        while (fd >= 0) {
            if (::write(fd, block.data(), block.size()) < 0) {
                error = errno;
                break;
            }
        }
        if (fd >= 0) ::close(fd);
        return error;
    }

private:
    ameoto::test::TempDir dir_;
    bool mounted_ = false;
    std::string why_;
};

std::string file_text(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST_CASE("who may talk: 127.0.0.1 by default, and nothing said about other machines") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime"}, {}, ameoto::test::DaemonOptions::patient());
    CHECK(d.listening_line().find("osc.udp://127.0.0.1:") != std::string::npos);
    CHECK(d.process().output().find("reachable from other machines") == std::string::npos);
    CHECK(d.process().output().find("--allow") == std::string::npos);
}

TEST_CASE("who may talk: --bind 0.0.0.0 is logged; --allow 127.0.0.2/32 answers 127.0.0.2, ignores 127.0.0.1 and counts it") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--bind", "0.0.0.0", "--allow", "127.0.0.2/32"}, {}, ameoto::test::DaemonOptions::patient());
    CHECK(d.listening_line().find("osc.udp://0.0.0.0:") != std::string::npos);
    CHECK(d.process().output().find("listening on 0.0.0.0, reachable from other machines (--bind)") != std::string::npos);
    CHECK(d.process().output().find("answering only senders in 127.0.0.2/32 (--allow)") != std::string::npos);

    ClientFrom outsider("127.0.0.1", d.port());
    ClientFrom insider("127.0.0.2", d.port());
    const auto status = ameoto::protocol::encode_message("/status", {});
    // Nothing at all comes back to an outsider: no /status.reply, and no /fail even for garbage.
    for (int i = 0; i < 5; ++i) outsider.send(status);
    outsider.send({'j', 'u', 'n', 'k'});
    outsider.send(ameoto::protocol::encode_message("/rain/rate", {OscArgument::from_float(900)}));
    CHECK(outsider.receive_address(500ms).empty());
    // The same requests from inside the network are answered.
    insider.send(status);
    CHECK(insider.receive_address(2s) == "/status.reply");
    insider.send({'j', 'u', 'n', 'k'});
    CHECK(insider.receive_address(2s) == "/fail");
    CHECK(outsider.receive_address(200ms).empty());

    CHECK(d.process().stop(SIGTERM, 5s) == 0);
    CHECK(d.process().output().find("load: 0 commands answered /fail busy, 7 datagrams dropped from senders outside --allow") !=
          std::string::npos);
}

TEST_CASE("who may talk: --bind :: --allow ::1/128 answers ::1 and drops IPv4 senders (seen as ::ffff:127.0.0.1)") {
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--bind", "::", "--allow", "::1/128"}, {}, ameoto::test::DaemonOptions::patient());
    CHECK(d.process().output().find("answering only senders in ::1/128 (--allow)") != std::string::npos);
    ClientFrom v6("::1", d.port());
    ClientFrom v4("127.0.0.1", d.port());
    const auto status = ameoto::protocol::encode_message("/status", {});
    v4.send(status);
    CHECK(v4.receive_address(500ms).empty());
    v6.send(status);
    CHECK(v6.receive_address(2s) == "/status.reply");
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
    CHECK(d.process().output().find("1 datagrams dropped from senders outside --allow") != std::string::npos);
}

TEST_CASE("who may talk: a bad --allow stops ameotod at the command line with the reason") {
    ameoto::test::ChildProcess p({AMEOTO_BIN_DIR "/ameotod", "--allow", "10.1.0.0/8", "--port", "0"});
    CHECK(p.wait(10s) == 2);
    CHECK(p.output().find("--allow: '10.1.0.0/8' has host bits set below the /8 prefix") != std::string::npos);
}

TEST_CASE("SIGKILL: the WAV reads back up to the last second") {
    const std::string wav = ameoto::test::temp_path("sigkill.wav");
    Daemon d({"--backend", "null", "--output", wav, "--realtime", "--rain", "20"}, {}, ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    // 2.5 s of audio, read from the audio clock (a loaded machine or the sanitizers render slower than
    // real time, so a wall-clock sleep would promise audio that was never made).
    const double rendered_s = ameoto::test::wait_for_audio(client, 2.5).args[10].number;
    d.process().stop(SIGKILL, 5s);
    const auto w = ameoto::test::read_wav(wav);
    REQUIRE_MESSAGE(w.ok, w.error);
    CHECK(w.is_float);
    CHECK(w.channels == 2);
    // The header is rewritten once a second (WavWriter), after the writer thread's 10 ms drain: what it
    // claims may lag the audio by up to 1 s + 10 ms, plus a 256-frame block; 250 ms more for scheduling
    // (the writer thread runs at normal priority on a machine that may be busy). At real-time pace or
    // slower, a second of wall time is at most a second of audio, so the bound holds in every build.
    const double seconds = static_cast<double>(w.frames) / 48000.0;
    MESSAGE(rendered_s << " s of audio rendered before SIGKILL; the killed WAV holds " << seconds << " s");
    CHECK(w.frames > 0);
    CHECK(seconds >= rendered_s - 1.0 - 0.010 - 256.0 / 48000.0 - 0.25);
    CHECK(seconds <= rendered_s + 0.5);   // 0.5 s: audio rendered between the last /status and the kill
    double energy = 0.0;
    for (float s : w.samples) {
        REQUIRE(std::isfinite(s));
        energy += static_cast<double>(s) * s;
    }
    CHECK(energy > 0.0);
}

TEST_CASE("disk full while writing the WAV: told over OSC and in the log, the audio keeps running, writing resumes with room") {
    SmallDisk disk("1m");   // 48 kHz stereo float is 384 KB/s: full after about 2.7 s
    if (!disk.mounted()) {
        MESSAGE("SKIPPED: cannot mount a tmpfs (" << disk.why() << "); needs root");
        return;
    }
    const std::string wav = (disk.path() / "full.wav").string();
    Daemon d({"--backend", "null", "--output", wav, "--realtime"}, {}, ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    const auto before = ameoto::test::audio_frames(client);   // the server knows this client now: it gets notices
    const auto notice = wait_for_notice(client, "failed", 10s);
    REQUIRE_MESSAGE(notice, d.process().output());
    CHECK(notice->args[0].text == "output");
    CHECK(notice->args[1].text.find("No space left on device") != std::string::npos);
    CHECK(d.process().output().find("writing " + wav + " failed: No space left on device") != std::string::npos);
    // Still playing: the sample clock runs on at the clock's pace, and the server answers.
    const auto at_full = ameoto::test::audio_frames(client);
    std::this_thread::sleep_for(1000ms);
    const auto later = ameoto::test::audio_frames(client);
    CHECK(at_full > before);
    CHECK(later > at_full);
    AMEOTO_CHECK_UNLESS_SANITIZED(later - at_full > 48000 / 2);   // at the clock's pace: half a second in one
    // One report, not one per block.
    CHECK_FALSE(wait_for_notice(client, "failed", 1500ms));
    // Room again (tmpfs grows on remount): writing resumes by itself, and says so.
    REQUIRE(disk.grow("16m"));
    const auto again = wait_for_notice(client, "again", 5s);
    REQUIRE_MESSAGE(again, d.process().output());
    CHECK(again->args[0].text == "output");
    CHECK(again->args[1].text.find("frames were lost") != std::string::npos);
    ameoto::test::wait_for_audio(client, 1.5);   // 1.5 s of audio after the room came (by the audio clock)
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
    const auto w = ameoto::test::read_wav(wav);   // what fitted, and what came after, reads back
    REQUIRE_MESSAGE(w.ok, w.error);
    CHECK(w.frames > (1 << 20) / 8 + 48000);   // more than 1 MiB holds (8 bytes a frame), and more than a second after it
}

TEST_CASE("the WAV removed while writing: told over OSC and in the log, the stream continues in a new file") {
    ameoto::test::TempDir dir("ameoto-removed");
    const std::string wav = (dir.path() / "removed.wav").string();
    Daemon d({"--backend", "null", "--output", wav, "--realtime"}, {}, ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    ameoto::test::audio_frames(client);
    std::this_thread::sleep_for(300ms);
    REQUIRE(fs::remove(wav));
    const auto notice = wait_for_notice(client, "was removed while writing", 3s);   // checked about once a second
    REQUIRE_MESSAGE(notice, d.process().output());
    CHECK(notice->args[0].text == "output");
    CHECK(notice->args[1].text.find("continuing in " + wav) != std::string::npos);
    CHECK(d.process().output().find(wav + " was removed while writing") != std::string::npos);
    const auto a = ameoto::test::audio_frames(client);
    std::this_thread::sleep_for(1200ms);
    const auto b = ameoto::test::audio_frames(client);
    CHECK(b > a);                                   // the stream goes on...
    AMEOTO_CHECK_UNLESS_SANITIZED(b - a > 48000);   // ...at the audio's pace: more than 1 s in 1.2 s
    ameoto::test::wait_for_audio(client, 1.1);      // another 1.1 s of audio (by the audio clock)...
    CHECK(d.process().stop(SIGTERM, 5s) == 0);
    const auto w = ameoto::test::read_wav(wav);   // ...is in the new file, finalised
    REQUIRE_MESSAGE(w.ok, w.error);
    CHECK(w.frames > 48000);
}

TEST_CASE("scene save on a full disk: /fail with the reason, the old scene file intact, no temporary left") {
    SmallDisk disk("64k");
    if (!disk.mounted()) {
        MESSAGE("SKIPPED: cannot mount a tmpfs (" << disk.why() << "); needs root");
        return;
    }
    Daemon d({"--backend", "null", "--output", "-", "--realtime", "--scene-dir", disk.path().string()}, {}, ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    const auto saved = client.request("/scene/save", {OscArgument::from_string("keep")}, "/done", 5s);
    REQUIRE(saved);
    const fs::path scene = disk.path() / "keep.scene";
    const std::string before = file_text(scene);
    REQUIRE(before.find("ameoto-scene 1") == 0);

    CHECK(disk.fill() == ENOSPC);
    client.send("/rain/rate", {OscArgument::from_float(33)});   // a scene that differs from the file
    const auto refused = client.request("/scene/save", {OscArgument::from_string("keep")}, "/fail", 5s);
    REQUIRE(refused);
    CHECK(refused->args[0].text == "/scene/save");
    CHECK(refused->args[1].text.find("No space left on device") != std::string::npos);
    CHECK(file_text(scene) == before);
    for (const auto& entry : fs::directory_iterator(disk.path()))
        CHECK_MESSAGE(entry.path().filename().string().find(".tmp") == std::string::npos, entry.path());

    fs::remove(disk.path() / "filler");   // room again: the same save goes through
    REQUIRE(client.request("/scene/save", {OscArgument::from_string("keep")}, "/done", 5s));
    CHECK(file_text(scene).find("rate=33") != std::string::npos);
}

TEST_CASE("JACK killed (SIGKILL) and started again: a /notice, OSC answers throughout, playing again within 2 s") {
    ameoto::test::JackServer jack;
    Daemon d({"--backend", "jack", "--jack-name", "ameoto_faults"}, jack.env(), ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    CHECK(ameoto::test::audio_frames(client) > 0);

    jack.kill();
    const auto lost = wait_for_notice(client, "went away", 10s);
    REQUIRE_MESSAGE(lost, d.process().output());
    CHECK(lost->args[0].text == "jack");
    CHECK(d.process().output().find("the JACK server went away") != std::string::npos);
    // A callback already running when jackd died may still finish its block (the clock moved 512 -> 768
    // under ASan in CI, with the notice already out): let it, then the clock must stand still.
    std::this_thread::sleep_for(300ms);
    const auto frozen = ameoto::test::audio_frames(client);   // answered while JACK is gone
    std::this_thread::sleep_for(300ms);
    CHECK(ameoto::test::audio_frames(client) == frozen);

    // The server is back somewhere between the start of jackd and jack_wait's return: playing again is
    // timed from the start (an upper bound on the delay the issue bounds) by a second client polling.
    std::atomic<bool> done{false};
    std::atomic<double> playing_after{-1.0};
    const auto restart = std::chrono::steady_clock::now();
    std::thread watcher([&] {
        OscTestClient poller(d.port());
        while (!done.load() && std::chrono::steady_clock::now() - restart < 10s) {
            const auto reply = poller.request("/status", {}, "/status.reply", 200ms);
            if (reply && std::llround(reply->args[10].number * reply->args[8].number) > frozen) {
                playing_after.store(std::chrono::duration<double>(std::chrono::steady_clock::now() - restart).count());
                return;
            }
            std::this_thread::sleep_for(10ms);
        }
    });
    jack.start();   // returns once jack_wait sees the server ready
    const double ready_after = std::chrono::duration<double>(std::chrono::steady_clock::now() - restart).count();
    watcher.join();
    done.store(true);
    MESSAGE("jackd started and ready (jack_wait) after " << ready_after << " s; ameotod playing again " << playing_after.load()
            << " s after jackd was started");
    CHECK(playing_after.load() >= 0.0);
    CHECK(playing_after.load() < 2.0);
    CHECK(wait_for_notice(client, "back", 2s));
    CHECK(d.process().running());
}
