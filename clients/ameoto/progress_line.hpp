#pragma once
// A render's progress on a terminal: "rendering: 42 %" rewritten in place on stderr, only when it
// changes, and wiped at the end. Silent when disabled (--quiet, or stderr is not a terminal).
//
// Interface:
//   ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr);
//   progress.show(done, total);   // after each block
//   progress.clear();             // when done

#include <ostream>

namespace ameoto::client {

class ProgressLine {
public:
    ProgressLine(std::ostream& out, bool enabled) : out_(out), enabled_(enabled) {}
    void show(long done, long total) {
        if (!enabled_ || total <= 0) return;
        const int percent = static_cast<int>(100 * done / total);
        if (percent == shown_) return;
        shown_ = percent;
        out_ << "\rrendering: " << percent << " %" << std::flush;
    }
    void clear() {
        if (enabled_) out_ << "\r                \r" << std::flush;
    }

private:
    std::ostream& out_;
    bool enabled_;
    int shown_ = -1;
};

}  // namespace ameoto::client
