// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The audio thread's real-time probe report (`ameotod --rt-report FILE`, server/realtime/rt_probe.hpp),
// read by the test thread once the daemon has stopped and written it:
//
//   const auto rt = ameoto::test::read_rt_report(path);
//   INFO(rt.text);
//   CHECK(rt.no_violations());   // the audio thread never allocated, freed, locked, blocked or logged
//   CHECK(rt.probed());          // and the probe was live in its callbacks (a report of 0 entries proves nothing)

#include <fstream>
#include <iterator>
#include <string>

namespace ameoto::test {

struct RtReport {
    std::string text;   // empty when the file could not be read
    bool no_violations() const { return text.find("violations 0\n") != std::string::npos; }
    bool probed() const { return !text.empty() && text.find("entries 0\n") == std::string::npos; }
};

inline RtReport read_rt_report(const std::string& path) {
    std::ifstream in(path);
    return {std::string((std::istreambuf_iterator<char>(in)), {})};
}

}  // namespace ameoto::test
