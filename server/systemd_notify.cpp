// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/systemd_notify.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>

namespace ameoto {

SystemdNotifier::SystemdNotifier() {
    std::uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) > 0) watchdog_interval_ = std::chrono::microseconds(usec / 2);
}

void SystemdNotifier::ready() { sd_notify(0, "READY=1"); }
void SystemdNotifier::status(const std::string& text) { sd_notify(0, ("STATUS=" + text).c_str()); }
void SystemdNotifier::watchdog() { sd_notify(0, "WATCHDOG=1"); }
void SystemdNotifier::stopping() { sd_notify(0, "STOPPING=1"); }

}  // namespace ameoto
