// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A process's resident memory, as the kernel counts it, for the tests that hold memory flat.
//
// Interface:
//   long kib = resident_kib(pid);   // /proc/PID/status VmRSS in KiB; -1 when the process is gone

#include <sys/types.h>

#include <fstream>
#include <string>

namespace ameoto::test {

inline long resident_kib(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string key;
    long value = -1;
    while (in >> key)
        if (key == "VmRSS:") {
            in >> value;
            break;
        }
    return value;
}

}  // namespace ameoto::test
