// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Where the built programs are, for tests that run them (AMEOTO_BIN_DIR comes from tests/CMakeLists.txt).
//
// Interface:
//   ameoto::test::ameotod      the daemon
//   ameoto::test::ameoto_bin   the command-line client

#include <string>

namespace ameoto::test {

inline const std::string ameotod = AMEOTO_BIN_DIR "/ameotod";
inline const std::string ameoto_bin = AMEOTO_BIN_DIR "/ameoto";

}  // namespace ameoto::test
