// SPDX-License-Identifier: GPL-3.0-or-later
// WavWriter under faults, without the daemon: the file removed while it is written (reported, a new file
// begun, the producer never refused), and a file that fails from the first write (/dev/full). A disk
// that fills midway is tested with the daemon on a real tmpfs (tests/integration/faults_test.cpp).

#include "server/backends/wav_writer.hpp"

#include <doctest/doctest.h>
#include <sndfile.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {
// Pushes `seconds` of 48 kHz stereo at about the real rate; counts pushes the ring refused.
int push_for(ameoto::WavWriter& w, double seconds) {
    std::vector<float> block(2 * 480, 0.25f);
    int refused = 0;
    for (int i = 0; i < static_cast<int>(seconds * 100); ++i) {
        if (!w.push(block.data(), 480)) ++refused;
        std::this_thread::sleep_for(10ms);
    }
    return refused;
}

std::string first_event(ameoto::WavWriter& w, const std::string& containing) {
    for (std::string e = w.take_error(); !e.empty(); e = w.take_error())
        if (e.find(containing) != std::string::npos) return e;
    return "";
}
}  // namespace

TEST_CASE("WavWriter: the file removed while writing is reported and the stream continues in a new file at the path") {
    ameoto::test::TempDir dir("ameoto-wav-removed");
    const std::string path = (dir.path() / "take.wav").string();
    ameoto::WavWriter w(path, 2, 48000.0);
    CHECK(push_for(w, 0.3) == 0);
    REQUIRE(fs::remove(path));
    CHECK(push_for(w, 1.5) == 0);   // the link count is checked about once a second
    const std::string event = first_event(w, "was removed while writing");
    CHECK_MESSAGE(!event.empty(), "no report");
    CHECK(event.find("continuing in " + path) != std::string::npos);
    CHECK(fs::exists(path));
    w.close();
    SF_INFO info{};
    SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
    REQUIRE(f != nullptr);
    CHECK(info.frames > 0);
    sf_close(f);
}

TEST_CASE("WavWriter: a file that cannot take even its header (/dev/full) is refused at the start, with the reason") {
    ameoto::test::TempDir dir("ameoto-wav-full");
    const fs::path link = dir.path() / "full.wav";
    fs::create_symlink("/dev/full", link);   // every write fails with ENOSPC
    std::string error;
    try {
        ameoto::WavWriter w(link.string(), 2, 48000.0);
    } catch (const std::runtime_error& e) {
        error = e.what();
    }
    CHECK(error.find("cannot open " + link.string() + " for writing") == 0);
    CHECK(error.find("No space left on device") != std::string::npos);
}
