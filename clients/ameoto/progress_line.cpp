// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/progress_line.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace ameoto::client {
namespace {

constexpr int default_columns = 80;
constexpr int min_bar = 10;   // narrower than this, a bar says less than the percentage next to it

std::string seconds_text(double seconds, double total_seconds) {
    char text[64];
    std::snprintf(text, sizeof text, "%.1f s of %.1f s", seconds, total_seconds);
    return text;
}

}  // namespace

std::string progress_text(long done, long total, double frames_per_second, int columns) {
    total = std::max(total, 1L);
    done = std::clamp(done, 0L, total);
    const int percent = static_cast<int>(100 * done / total);
    char percent_text[16];
    std::snprintf(percent_text, sizeof percent_text, "%3d %%", percent);   // fixed width: the bar does not jump
    const int room = std::max(columns, 1) - 1;

    std::string time;
    if (frames_per_second > 0) {
        const double total_s = static_cast<double>(total) / frames_per_second;
        time = seconds_text(static_cast<double>(done) / frames_per_second, total_s);
        // Padded to its widest (at the end) so the line keeps its length as the seconds grow.
        const std::size_t widest = seconds_text(total_s, total_s).size();
        if (time.size() < widest) time.insert(0, widest - time.size(), ' ');
        time = "  " + time;
    }
    const std::string head = "rendering [", tail = std::string("] ") + percent_text;
    const int fixed = static_cast<int>(head.size() + tail.size());
    if (room - fixed - static_cast<int>(time.size()) < min_bar) time.clear();
    const int bar = room - fixed - static_cast<int>(time.size());
    if (bar < min_bar) return std::string("rendering ") + percent_text;

    const int filled = static_cast<int>(static_cast<long long>(bar) * done / total);
    return head + std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(bar - filled), '.') + tail +
           time;
}

int terminal_columns() {
    winsize size{};
    if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
    if (const char* columns = std::getenv("COLUMNS")) {
        char* end = nullptr;
        const long n = std::strtol(columns, &end, 10);
        if (end != columns && *end == '\0' && n > 0 && n <= 10000) return static_cast<int>(n);
    }
    return default_columns;
}

void ProgressLine::show(long done, long total) {
    if (!enabled_ || total <= 0) return;
    std::string text = progress_text(done, total, frames_per_second_, columns_);
    if (text == shown_) return;   // a terminal redrawn every block would flicker and cost the render time
    out_ << '\r' << text << std::flush;
    shown_ = std::move(text);
}

void ProgressLine::clear() {
    if (!enabled_ || shown_.empty()) return;
    out_ << '\r' << std::string(shown_.size(), ' ') << '\r' << std::flush;
    shown_.clear();
}

}  // namespace ameoto::client
