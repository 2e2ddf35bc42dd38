// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// systemd's watchdog (WatchdogSec=): WATCHDOG=1 only while the audio clock advances, so a stalled audio
// thread, not just a stalled control loop, lets systemd restart ameotod (docs/systemd.md).
//
// Interface:
//   Watchdog watchdog(systemd);
//   watchdog.interval()              // half of WatchdogSec; 0: no watchdog asked for, nothing to do
//   watchdog.feed(bridge.snapshot().frames);   // every interval: WATCHDOG=1 when frames moved since the last
//
// Thread: the control thread only.

#include <chrono>
#include <cstdint>

#include "server/systemd_notify.hpp"

namespace ameoto {

class Watchdog {
public:
    explicit Watchdog(SystemdNotifier& systemd) : systemd_(systemd) {}
    std::chrono::microseconds interval() const { return systemd_.watchdog_interval(); }
    void feed(std::uint64_t frames) {
        if (frames != last_frames_) systemd_.watchdog();
        last_frames_ = frames;
    }

private:
    SystemdNotifier& systemd_;
    std::uint64_t last_frames_ = 0;
};

}  // namespace ameoto
