// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Talks to systemd when ameotod runs as a Type=notify service; does nothing elsewhere.
//
// Interface:
//   SystemdNotifier sd;
//   sd.ready();                       // READY=1: only once audio runs and the port is bound
//   sd.status("...");                 // STATUS= line shown by systemctl status
//   sd.watchdog_interval()            // half of WatchdogSec, or 0 when no watchdog is set
//   sd.watchdog();                    // WATCHDOG=1: the caller sends it only while audio advances
//   sd.stopping();                    // STOPPING=1

#include <chrono>
#include <string>

namespace ameoto {

class SystemdNotifier {
public:
    SystemdNotifier();
    void ready();
    void status(const std::string& text);
    void watchdog();
    void stopping();
    std::chrono::microseconds watchdog_interval() const { return watchdog_interval_; }

private:
    std::chrono::microseconds watchdog_interval_{0};
};

}  // namespace ameoto
