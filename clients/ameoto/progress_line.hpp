// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A render's progress on a terminal: a bar that fits the terminal's width, rewritten in place on stderr
// only when its text changes, and wiped at the end. Silent when disabled (--quiet, or stderr is not a
// terminal).
//
//   rendering [##########..............] 42 %  12.6 s of 30.0 s
//
// Interface:
//   ProgressLine progress(io.err, !o.quiet && isatty(STDERR_FILENO) && &io.err == &std::cerr, o.rate);
//   progress.show(done, total);   // after each block (frames; seconds shown when the rate is given)
//   progress.clear();             // when done
//   progress_text(done, total, frames_per_second, columns)   // the line itself, for tests
//   terminal_columns()            // stderr's width (TIOCGWINSZ), else $COLUMNS, else 80

#include <ostream>
#include <string>

namespace ameoto::client {

// The line for `done` of `total` frames in at most columns - 1 characters (a full last column makes some
// terminals wrap). It narrows by dropping the seconds, then the bar: "rendering 42 %" always fits.
// frames_per_second <= 0: no seconds.
std::string progress_text(long done, long total, double frames_per_second, int columns);

int terminal_columns();

class ProgressLine {
public:
    ProgressLine(std::ostream& out, bool enabled, double frames_per_second = 0.0)
        : ProgressLine(out, enabled, frames_per_second, enabled ? terminal_columns() : 80) {}
    ProgressLine(std::ostream& out, bool enabled, double frames_per_second, int columns)
        : out_(out), enabled_(enabled), frames_per_second_(frames_per_second), columns_(columns) {}
    void show(long done, long total);
    void clear();

private:
    std::ostream& out_;
    bool enabled_;
    double frames_per_second_;
    int columns_;
    std::string shown_;
};

}  // namespace ameoto::client
