// SPDX-License-Identifier: GPL-3.0-or-later
// The render's progress bar (clients/ameoto/progress_line.hpp): fits the terminal, keeps its length,
// narrows gracefully, is rewritten only when its text changes, is wiped at the end, and is silent when
// disabled.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>

#include "clients/ameoto/progress_line.hpp"

using ameoto::client::progress_text;
using ameoto::client::ProgressLine;

namespace {
long count(const std::string& text, char c) { return static_cast<long>(std::count(text.begin(), text.end(), c)); }
}  // namespace

TEST_CASE("the bar shows the fraction done, the percentage and the seconds, in one column less than the terminal") {
    // 12.6 s of 30 s at 48 kHz: 42 %.
    const std::string line = progress_text(604800, 1440000, 48000.0, 80);
    CHECK(line.size() == 79);
    CHECK(line.starts_with("rendering ["));
    CHECK(line.ends_with("]  42 %  12.6 s of 30.0 s"));
    const long bar = count(line, '#') + count(line, '.') - 2;   // the two dots of the seconds
    CHECK(bar == 79 - static_cast<long>(std::string("rendering []  42 %  12.6 s of 30.0 s").size()));
    CHECK(count(line, '#') == bar * 42 / 100);   // 604800 / 1440000 = 0.42 exactly

    CHECK(progress_text(0, 1440000, 48000.0, 80).find('#') == std::string::npos);
    const std::string full = progress_text(1440000, 1440000, 48000.0, 80);
    CHECK(full.find("] 100 %  30.0 s of 30.0 s") != std::string::npos);
    CHECK(full.find('.') == full.find("30.0") + 2);   // no empty cell left: the first '.' is the seconds'
}

TEST_CASE("the line keeps its length from start to end, so rewriting it in place leaves nothing behind") {
    const long total = 30 * 48000;
    const std::size_t length = progress_text(0, total, 48000.0, 100).size();
    for (long done = 0; done <= total; done += 48000) CHECK(progress_text(done, total, 48000.0, 100).size() == length);
    CHECK(length == 99);
}

TEST_CASE("narrow terminals drop the seconds, then the bar; without a rate there are no seconds") {
    const std::string medium = progress_text(50, 100, 10.0, 40);
    CHECK(medium.size() <= 39);
    CHECK(medium.find(" s of ") == std::string::npos);
    CHECK(medium.find('[') != std::string::npos);
    CHECK(progress_text(50, 100, 10.0, 20) == "rendering  50 %");
    CHECK(progress_text(50, 100, 10.0, 1) == "rendering  50 %");
    const std::string no_rate = progress_text(50, 100, 0.0, 80);
    CHECK(no_rate.size() == 79);
    CHECK(no_rate.ends_with("]  50 %"));
    // Out-of-range counts are clamped, never a bar longer than the line.
    CHECK(progress_text(500, 100, 0.0, 80) == progress_text(100, 100, 0.0, 80));
    CHECK(progress_text(-5, 100, 0.0, 80) == progress_text(0, 100, 0.0, 80));
}

TEST_CASE("ProgressLine writes only when the text changes, wipes itself at the end, and is silent when disabled") {
    std::ostringstream out;
    {
        ProgressLine progress(out, true, 0.0, 40);
        for (long done = 0; done <= 1000; ++done) progress.show(done, 1000);   // 1001 calls, 101 different percentages
        const std::string written = out.str();
        // One rewrite per change of the text: the percentage's 101 values, plus the bar's cells (21 at
        // 40 columns) where one fills between two percentages; never one per call.
        long changes = 1;
        for (long done = 1; done <= 1000; ++done) changes += progress_text(done, 1000, 0.0, 40) != progress_text(done - 1, 1000, 0.0, 40);
        CHECK(count(written, '\r') == changes);
        CHECK(changes >= 101);
        CHECK(changes <= 101 + 21);
        const std::string last = written.substr(written.rfind('\r') + 1);
        CHECK(last == progress_text(1000, 1000, 0.0, 40));
        out.str("");
        progress.clear();
        std::string wipe(last.size() + 2, ' ');   // built in place: GCC 12 misreads "\r" + string + "\r" (-Wrestrict)
        wipe.front() = wipe.back() = '\r';
        CHECK(out.str() == wipe);
    }
    std::ostringstream quiet;
    ProgressLine silent(quiet, false, 48000.0, 80);
    silent.show(1, 2);
    silent.clear();
    CHECK(quiet.str().empty());
}

TEST_CASE("the width comes from the terminal, else $COLUMNS, else 80") {
    // Under the test runner stderr is usually not a terminal; then COLUMNS decides. On a terminal the
    // ioctl answers first and the COLUMNS checks are skipped (they would test the terminal instead).
    if (isatty(2)) return;
    setenv("COLUMNS", "132", 1);
    CHECK(ameoto::client::terminal_columns() == 132);
    setenv("COLUMNS", "wide", 1);
    CHECK(ameoto::client::terminal_columns() == 80);
    unsetenv("COLUMNS");
    CHECK(ameoto::client::terminal_columns() == 80);
}
