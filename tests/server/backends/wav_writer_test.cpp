// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/wav_writer.hpp"

#include <doctest/doctest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
fs::path temp_dir() {
    fs::path d = fs::temp_directory_path() / ("ameoto-wav-test-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}
std::vector<float> read_all(const std::string& path, SF_INFO& info) {
    info = SF_INFO{};
    SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
    REQUIRE(f != nullptr);
    std::vector<float> data(static_cast<std::size_t>(info.frames * info.channels));
    CHECK(sf_readf_float(f, data.data(), info.frames) == info.frames);
    sf_close(f);
    return data;
}
}  // namespace

TEST_CASE("WavWriter writes every pushed sample bit-exactly as 32-bit float") {
    const fs::path dir = temp_dir();
    const std::string path = (dir / "exact.wav").string();
    fs::remove(path);
    std::vector<float> pushed;
    {
        ameoto::WavWriter w(path, 2, 48000.0);
        std::vector<float> block(2 * 256);
        for (int b = 0; b < 100; ++b) {
            for (std::size_t i = 0; i < block.size(); ++i) block[i] = std::sin(0.001f * static_cast<float>(b * 512 + static_cast<int>(i)));
            while (!w.push(block.data(), 256)) {}
            pushed.insert(pushed.end(), block.begin(), block.end());
        }
    }   // destructor drains and finalises
    SF_INFO info;
    const auto data = read_all(path, info);
    CHECK(info.channels == 2);
    CHECK(info.samplerate == 48000);
    CHECK((info.format & SF_FORMAT_SUBMASK) == SF_FORMAT_FLOAT);
    CHECK(data == pushed);
    fs::remove_all(dir);
}

TEST_CASE("WavWriter reopen never overwrites and both files are whole") {
    const fs::path dir = temp_dir();
    const std::string path = (dir / "take.wav").string();
    {
        ameoto::WavWriter w(path, 1, 8000.0);
        std::vector<float> ones(800, 1.0f);
        REQUIRE(w.push(ones.data(), 800));
        while (w.frames_written() < 800) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        w.reopen();
        while (w.path() == path) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::vector<float> twos(400, 2.0f);
        REQUIRE(w.push(twos.data(), 400));
    }
    SF_INFO info;
    CHECK(read_all(path, info).size() == 800);
    const std::string second = (dir / "take-1.wav").string();
    REQUIRE(fs::exists(second));
    const auto data = read_all(second, info);
    CHECK(data.size() == 400);
    CHECK(data.front() == 2.0f);
    fs::remove_all(dir);
}

TEST_CASE("WavWriter refuses a path it cannot write, with the reason") {
    CHECK_THROWS_WITH_AS(ameoto::WavWriter("/nonexistent-dir/x.wav", 2, 48000.0), doctest::Contains("cannot open"), std::runtime_error);
}

TEST_CASE("unused_path adds a counter before the extension") {
    const fs::path dir = temp_dir();
    const std::string p = (dir / "a.wav").string();
    CHECK(ameoto::unused_path(p) == p);
    { std::FILE* f = std::fopen(p.c_str(), "w"); std::fclose(f); }
    CHECK(ameoto::unused_path(p) == (dir / "a-1.wav").string());
    fs::remove_all(dir);
}
