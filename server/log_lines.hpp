// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ameotod's log: one line each, "ameotod: ..." on stdout for what happens, on stderr for what went
// wrong. Flushed at once: scripts and the tests wait for these lines (daemon.hpp lists the ones they
// may rely on).
//
// Interface:
//   say("running");                       // stdout
//   warn("cannot use JACK: ...");         // stderr
//
// Thread: the control thread, and the main thread before and after the control loop runs. Never the
// audio thread (it never logs: docs/architecture.md, "The real-time contract").

#include <iostream>
#include <string>

namespace ameoto {

inline void say(const std::string& line) { std::cout << "ameotod: " << line << std::endl; }
inline void warn(const std::string& line) { std::cerr << "ameotod: " << line << std::endl; }

}  // namespace ameoto
