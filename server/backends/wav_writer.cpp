#include "server/backends/wav_writer.hpp"

#include <sndfile.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

namespace ameoto {

std::string unused_path(const std::string& path) {
    namespace fs = std::filesystem;
    if (!fs::exists(path)) return path;
    const fs::path p(path);
    for (int i = 1;; ++i) {
        fs::path candidate = p.parent_path() / (p.stem().string() + "-" + std::to_string(i) + p.extension().string());
        if (!fs::exists(candidate)) return candidate.string();
    }
}

WavWriter::WavWriter(std::string path, int channels, double sample_rate, double buffer_seconds)
    : requested_path_(std::move(path)),
      channels_(channels),
      sample_rate_(sample_rate),
      ring_(static_cast<std::size_t>(buffer_seconds * sample_rate) * static_cast<std::size_t>(channels)) {
    open_file(requested_path_);
    if (!file_) throw std::runtime_error(error_);
    thread_ = std::thread([this] { run(); });
}

WavWriter::~WavWriter() { close(); }

void WavWriter::open_file(const std::string& path) {
    SF_INFO info{};
    info.samplerate = static_cast<int>(sample_rate_);
    info.channels = channels_;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
    std::lock_guard lock(file_mutex_);
    if (!f) {
        error_ = "cannot open " + path + " for writing: " + sf_strerror(nullptr);
        return;
    }
    file_ = f;
    path_ = path;
}

void WavWriter::close_file() {
    std::lock_guard lock(file_mutex_);
    if (file_) {
        sf_write_sync(file_);
        sf_close(file_);   // rewrites the header with the final sizes
        file_ = nullptr;
    }
}

void WavWriter::write_pending() {
    std::vector<float> chunk(static_cast<std::size_t>(channels_) * 4096);
    for (;;) {
        const std::size_t got = ring_.read(chunk.data(), chunk.size());
        if (got == 0) return;
        const sf_count_t frames = static_cast<sf_count_t>(got / static_cast<std::size_t>(channels_));
        std::lock_guard lock(file_mutex_);
        if (!file_) continue;   // a failed reopen: keep draining so the audio never waits
        const sf_count_t written = sf_writef_float(file_, chunk.data(), frames);
        if (written != frames) error_ = "writing " + path_ + " failed: " + sf_strerror(file_);
        frames_written_ += static_cast<std::uint64_t>(written);
    }
}

void WavWriter::run() {
    auto last_header = std::chrono::steady_clock::now();
    while (!stop_.load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        write_pending();
        if (reopen_.exchange(false)) {
            close_file();
            open_file(unused_path(requested_path_));
        }
        const auto now = std::chrono::steady_clock::now();
        if (now - last_header >= std::chrono::seconds(1)) {
            std::lock_guard lock(file_mutex_);
            if (file_) sf_command(file_, SFC_UPDATE_HEADER_NOW, nullptr, 0);
            last_header = now;
        }
    }
    write_pending();
    close_file();
}

bool WavWriter::push(const float* interleaved, int frames) {
    return ring_.write(interleaved, static_cast<std::size_t>(frames) * static_cast<std::size_t>(channels_));
}

void WavWriter::reopen() { reopen_.store(true); }

void WavWriter::close() {
    if (thread_.joinable()) {
        stop_.store(true);
        thread_.join();
    }
}

std::string WavWriter::path() const {
    std::lock_guard lock(file_mutex_);
    return path_;
}

std::string WavWriter::take_error() {
    std::lock_guard lock(file_mutex_);
    return std::exchange(error_, std::string());
}

}  // namespace ameoto
