// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/real_clients/real_programs.hpp"

#include "protocol/address_table.hpp"

#include <doctest/doctest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "tests/support/audio_clock.hpp"
#include "tests/support/timing_scale.hpp"

namespace ameoto::test {

std::optional<std::string> find_program(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream folders(path ? path : "/usr/bin:/bin");
    for (std::string folder; std::getline(folders, folder, ':');) {
        const std::string candidate = (folder.empty() ? "." : folder) + "/" + name;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return std::nullopt;
}

void skip_because_absent(const std::string& program, const std::string& debian_package) {
    // Not a pass: a test that did not run says so (CI installs the package, so there it runs).
    MESSAGE("SKIPPED: " << program << " is not installed (Debian package " << debian_package
                        << ", installed by scripts/install-deps)");
}

std::string client_path(const std::string& relative) { return std::string(AMEOTO_SOURCE_DIR) + "/clients/" + relative; }

std::string test_file(const std::string& relative) {
    return std::string(AMEOTO_SOURCE_DIR) + "/tests/real_clients/" + relative;
}

double settled_rain_rate(OscTestClient& client) {
    // /rain/rate ramps linearly over 1 s of audio (docs/PROTOCOL.md). The caller has seen a reply sent
    // after the change (/synced, or the program's own), so it was applied before wait_for_audio's first
    // /status: once the audio clock has moved on 1.05 s from that reading, the ramp is over.
    return wait_for_audio(client, 1.05).args[11].number;
}

std::map<std::string, std::string> name_value_lines(const std::string& output, const std::string& prefix) {
    std::map<std::string, std::string> fields;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind(prefix, 0) != 0) continue;
        const std::string rest = line.substr(prefix.size());
        const auto space = rest.find(' ');
        if (space == std::string::npos) fields[rest] = "";
        else fields[rest.substr(0, space)] = rest.substr(space + 1);
    }
    return fields;
}

void check_oscdump_messages(const std::string& seen, std::span<const char* const> expected) {
    for (const char* line : expected) {
        CAPTURE(line);
        CHECK(seen.find(std::string(" ") + line + "\n") != std::string::npos);
    }
    std::istringstream lines(seen);
    int messages = 0;
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string timetag, address;
        words >> timetag >> address;
        if (address.empty()) continue;
        ++messages;
        CAPTURE(address);
        CHECK(ameoto::protocol::find_address(address) != nullptr);
    }
    CHECK(messages == static_cast<int>(expected.size()));
}

}  // namespace ameoto::test
