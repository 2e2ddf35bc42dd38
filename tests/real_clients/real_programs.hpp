// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the tests of the shipped clients share: finding the real programs, the paths of the clients
// in the source tree, and the server's settled state as its own /status reports it.
//
// Interface:
//   std::optional<std::string> pd = find_program("pd");   // its path in PATH, or nullopt
//   if (!pd) { skip_because_absent("pd", "puredata-core"); return; }   // says so in the test output
//   client_path("pd")                                      // AMEOTO_SOURCE_DIR "/clients/pd"
//   test_file("pd/ameoto_client_test.pd")                  // AMEOTO_SOURCE_DIR "/tests/real_clients/..."
//   double rate = settled_rain_rate(client);               // mm/h, once a ramp (1 s of audio) has finished
//   std::map<std::string, std::string> fields = name_value_lines(output, "status: ");

#include <map>
#include <optional>
#include <span>
#include <string>

#include "tests/support/daemon_process.hpp"
#include "tests/support/osc_test_client.hpp"

namespace ameoto::test {

std::optional<std::string> find_program(const std::string& name);
void skip_because_absent(const std::string& program, const std::string& debian_package);
std::string client_path(const std::string& relative);
std::string test_file(const std::string& relative);

// The server's rain rate (/status.reply field 12) after waiting out the 1 s ramp of /rain/rate.
double settled_rain_rate(OscTestClient& client);

// Lines "PREFIX NAME VALUE..." of a program's output, as NAME -> "VALUE...".
std::map<std::string, std::string> name_value_lines(const std::string& output, const std::string& prefix);

// ameotod builds its scene before it says "running"; on a machine busy with builds that has taken
// over 10 s (the default), so these tests, which run beside the other suites, wait up to 20 s.

// oscdump's lines (`TIMETAG ADDRESS TYPES VALUES...`) hold every expected message, exactly as many
// messages as expected, and every address is in the server's protocol table.
void check_oscdump_messages(const std::string& seen, std::span<const char* const> expected);

}  // namespace ameoto::test
