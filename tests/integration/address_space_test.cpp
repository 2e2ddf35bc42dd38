// SPDX-License-Identifier: GPL-3.0-or-later
// The whole address space against the real daemon over real UDP, generated from the protocol table
// (tests/protocol/table_cases.hpp): every bad message gets `/fail ADDRESS REASON`, the state is as it
// was (/status.reply and the scene saved before and after), and the server keeps serving. Bad scene
// files over /scene/load: refused with the file, line and field, and the scene plays on.

#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "protocol/address_table.hpp"
#include "tests/protocol/table_cases.hpp"
#include "tests/support/audio_clock.hpp"
#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/temp_dir.hpp"

using namespace std::chrono_literals;
using ameoto::protocol::DecodedMessage;
using ameoto::protocol::OscArgument;
using ameoto::test::OscTestClient;
using Daemon = ameoto::test::DaemonProcess;

namespace {

// What /status.reply says about the state (not the load or the clock, which move on their own):
// rain rate, sample rate, block size, backend.
std::string status_state(const DecodedMessage& status) {
    std::ostringstream s;
    s << "rate " << status.args[11].number << ", " << status.args[8].number << " Hz, block " << status.args[9].integer << ", "
      << status.args[12].text;
    return s.str();
}

// The scene as it plays: saved by the daemon itself, read back without its name line.
std::string saved_scene(OscTestClient& client, const std::filesystem::path& folder, const std::string& name) {
    const auto done = client.request("/scene/save", {OscArgument::from_string(name)}, "/done", 5s);
    REQUIRE_MESSAGE(done, "no /done for /scene/save " << name);
    std::ifstream in(folder / (name + ".scene"));
    std::string text, line;
    while (std::getline(in, line))
        if (line.rfind("name ", 0) != 0) text += line + "\n";
    REQUIRE(!text.empty());
    return text;
}

// A /fail naming the address, with a reason; everything else that arrived is kept in client.others.
void expect_fail(OscTestClient& client, const std::string& address) {
    const auto fail = client.wait_for("/fail", 2s);
    REQUIRE_MESSAGE(fail, "no /fail");
    REQUIRE(fail->types == "ss");
    CHECK(fail->args[0].text == address);
    CHECK_FALSE(fail->args[1].text.empty());
}

}  // namespace

TEST_CASE("every address refuses every bad message over UDP with /fail, the state unchanged, the server serving") {
    ameoto::test::TempDir folder("ameoto-address-space");
    // A dry start so the saved scene and the status are the daemon's state, nothing else.
    Daemon d({"--backend", "null", "--output", "-", "--rain", "3", "--scene-dir", folder.path().string()}, {}, ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    const std::string before_status = status_state(ameoto::test::status_reply(client));
    const std::string before_scene = saved_scene(client, folder.path(), "before");
    const double seconds_before = ameoto::test::status_reply(client).args[10].number;   // field 11: audio seconds

    std::size_t sent = 0;
    for (const ameoto::protocol::AddressSpec& spec : ameoto::protocol::address_table()) {
        for (const ameoto::test::BadCase& c : ameoto::test::bad_cases(spec)) {
            INFO(spec.address << " " << c.what);
            client.send(spec.address, c.args);
            expect_fail(client, spec.address);
            ++sent;
        }
    }
    for (const ameoto::test::BadPacket& b : ameoto::test::bad_packets()) {
        INFO(b.what);
        client.send_raw(b.bytes);
        const auto fail = client.wait_for("/fail", 2s);
        REQUIRE_MESSAGE(fail, "no /fail");
        CHECK_FALSE(fail->args[1].text.empty());
        ++sent;
    }
    // An unknown address, and one longer than any real one.
    client.send("/rain/rate/extra", {OscArgument::from_float(1.0f)});
    expect_fail(client, "/rain/rate/extra");
    std::string long_address(1001, 'x');
    long_address[0] = '/';
    client.send(long_address, {});
    expect_fail(client, long_address);
    // Valid arguments that would make the scene invalid: the carried umbrella (0.3 m above the ears)
    // pushed past the scene's 1000 m range, which /scene/save could then not write.
    client.send("/listener", {OscArgument::from_float(0), OscArgument::from_float(0), OscArgument::from_float(1000)});
    expect_fail(client, "/listener");
    // A custom umbrella material whose name a scene file cannot hold (names are 1-32 characters).
    client.send("/material/surface", {OscArgument::from_string("umbrella"), OscArgument::from_string(std::string(40, 'm')),
                                      OscArgument::from_float(0.1f), OscArgument::from_float(100), OscArgument::from_float(1),
                                      OscArgument::from_float(1e-5f)});
    expect_fail(client, "/material/surface");
    // The largest datagram IPv4 carries (65507 bytes): a scene name of 65 400 characters.
    client.send("/scene/load", {OscArgument::from_string(std::string(65400, 'a'))});
    expect_fail(client, "/scene/load");
    MESSAGE(sent << " bad messages and packets refused");

    // Nothing else came back: no /done, no /synced, no second reply to anything.
    CHECK(client.others.empty());
    for (const auto& other : client.others) MESSAGE("unexpected reply " << other.address);
    // Still serving, still playing, and in the state it was.
    REQUIRE(client.request("/sync", {OscArgument::from_int(42)}, "/synced", 2s));
    const DecodedMessage after = ameoto::test::status_reply(client);
    CHECK(status_state(after) == before_status);
    CHECK(after.args[10].number > seconds_before);
    CHECK(saved_scene(client, folder.path(), "after") == before_scene);
    CHECK(d.process().running());
}

TEST_CASE("bad scene files over /scene/load fail with the file, line and field; the scene plays on unchanged") {
    ameoto::test::TempDir folder("ameoto-bad-scenes");
    const auto write = [&](const std::string& name, const std::string& text) { std::ofstream(folder.path() / (name + ".scene")) << text; };
    write("malformed", "ameoto-scene 1\nname malformed\nrain rate=two\n");
    write("truncated", "ameoto-scene 1\nname truncated\nsurface roof kind=plate material=tin size=3x");
    write("future", "ameoto-scene 999\nname future\n");   // newer than any reader
    write("huge", "ameoto-scene 1\n" + std::string(70 * 1024, '#') + "\n");
    write("longline", "ameoto-scene 1\n# " + std::string(2000, 'x') + "\n");
    write("unknown", "ameoto-scene 1\nname unknown\nlistener x=0 y=0 z=1.6 height=3\n");
    std::filesystem::create_symlink("/etc/passwd", folder.path() / "linked.scene");
    struct Expect {
        const char* name;
        std::string says;
    };
    const Expect expected[] = {
        {"malformed", "malformed.scene:3: rate: "},
        {"truncated", "truncated.scene:3: size: "},
        {"future", "future.scene:1: "},
        {"huge", "huge.scene: "},
        {"longline", "longline.scene:2: "},
        {"unknown", "unknown.scene:3: height: "},
        {"linked", "linked.scene"},
    };
    Daemon d({"--backend", "null", "--output", "-", "--scene", "pond", "--scene-dir", folder.path().string()}, {}, ameoto::test::DaemonOptions::patient());
    OscTestClient client(d.port());
    const std::string before_status = status_state(ameoto::test::status_reply(client));
    const std::string before_scene = saved_scene(client, folder.path(), "before");
    for (const Expect& e : expected) {
        INFO(std::string(e.name));
        const auto fail = client.request("/scene/load", {OscArgument::from_string(e.name)}, "/fail", 5s);
        REQUIRE(fail);
        CHECK(fail->args[0].text == "/scene/load");
        INFO(fail->args[1].text);
        CHECK(fail->args[1].text.find(e.says) != std::string::npos);
        const double seconds = ameoto::test::status_reply(client).args[10].number;
        std::this_thread::sleep_for(50ms);
        CHECK(ameoto::test::status_reply(client).args[10].number > seconds);   // playing on
    }
    CHECK(client.others.empty());
    CHECK(status_state(ameoto::test::status_reply(client)) == before_status);
    CHECK(saved_scene(client, folder.path(), "after") == before_scene);
}
