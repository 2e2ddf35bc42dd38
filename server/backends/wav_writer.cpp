// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/wav_writer.hpp"

#include <fcntl.h>
#include <sndfile.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
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
    if (!file_) throw std::runtime_error(take_error());
    thread_ = std::thread([this] { run(); });
}

WavWriter::~WavWriter() { close(); }

void WavWriter::open_file(const std::string& path) {
    SF_INFO info{};
    info.samplerate = static_cast<int>(sample_rate_);
    info.channels = channels_;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    // Opened here rather than by sf_open so the descriptor is ours to fstat (has the file been removed?).
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);   // as sf_open does for SFM_WRITE
    const int open_errno = errno;
    SNDFILE* f = fd >= 0 ? sf_open_fd(fd, SFM_WRITE, &info, SF_TRUE) : nullptr;
    std::lock_guard lock(file_mutex_);
    if (!f) {
        report("cannot open " + path + " for writing: " + (fd < 0 ? std::strerror(open_errno) : sf_strerror(nullptr)));
        if (fd >= 0) ::close(fd);
        return;
    }
    file_ = f;
    fd_ = fd;
    failing_ = false;
    path_ = path;
    sf_set_string(file_, SF_STR_SOFTWARE, "ameotod " AMEOTO_VERSION);
    if (!comment_.empty()) sf_set_string(file_, SF_STR_COMMENT, comment_.c_str());
}

// libsndfile writes the strings into the LIST/INFO chunk when the file is finalised (close, SIGHUP).
void WavWriter::set_comment(const std::string& text) {
    std::lock_guard lock(file_mutex_);
    comment_ = text;
    if (file_) sf_set_string(file_, SF_STR_COMMENT, comment_.c_str());
}

void WavWriter::report(std::string event) {
    if (events_.size() < 16) events_.push_back(std::move(event));   // bounded: a control thread that never asks
}

void WavWriter::check_still_linked() {
    std::string removed;
    {
        std::lock_guard lock(file_mutex_);
        struct stat st {};
        if (!file_ || fstat(fd_, &st) != 0 || st.st_nlink > 0) return;
        removed = path_;
    }
    close_file();
    open_file(unused_path(requested_path_));
    std::lock_guard lock(file_mutex_);
    if (file_) report(removed + " was removed while writing (what it held is gone with it); continuing in " + path_);
}

void WavWriter::close_file() {
    std::lock_guard lock(file_mutex_);
    if (file_) {
        sf_write_sync(file_);
        sf_close(file_);   // rewrites the header with the final sizes, closes fd_
        file_ = nullptr;
        fd_ = -1;
    }
}

void WavWriter::write_pending() {
    std::vector<float> chunk(static_cast<std::size_t>(channels_) * 4096);
    for (;;) {
        const std::size_t got = ring_.read(chunk.data(), chunk.size());
        if (got == 0) return;
        const sf_count_t frames = static_cast<sf_count_t>(got / static_cast<std::size_t>(channels_));
        std::lock_guard lock(file_mutex_);
        if (!file_) {   // a failed reopen: keep draining so the audio never waits
            frames_lost_ += static_cast<std::uint64_t>(frames);
            continue;
        }
        errno = 0;
        const sf_count_t written = sf_writef_float(file_, chunk.data(), frames);
        const int write_errno = errno;
        if (written != frames && !failing_) {
            failing_ = true;
            report("writing " + path_ + " failed: " + (write_errno ? std::strerror(write_errno) : sf_strerror(file_)) +
                   "; the audio keeps running, samples that cannot be written are dropped");
        } else if (written == frames && failing_) {
            failing_ = false;
            report("writing " + path_ + " again, after " + std::to_string(frames_lost_.load()) + " frames were lost in all");
        }
        frames_written_ += static_cast<std::uint64_t>(std::max<sf_count_t>(written, 0));
        frames_lost_ += static_cast<std::uint64_t>(frames - std::max<sf_count_t>(written, 0));
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
            {
                std::lock_guard lock(file_mutex_);
                if (file_) sf_command(file_, SFC_UPDATE_HEADER_NOW, nullptr, 0);
            }
            check_still_linked();
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
    if (events_.empty()) return "";
    std::string event = std::move(events_.front());
    events_.pop_front();
    return event;
}

}  // namespace ameoto
