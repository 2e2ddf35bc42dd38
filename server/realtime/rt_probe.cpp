// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/realtime/rt_probe.hpp"

#include <dlfcn.h>

namespace ameoto::rt {

void (*probe_enter)() = nullptr;
void (*probe_leave)() = nullptr;

void init_probe() {
    probe_enter = reinterpret_cast<void (*)()>(dlsym(RTLD_DEFAULT, "ameoto_rt_probe_enter"));
    probe_leave = reinterpret_cast<void (*)()>(dlsym(RTLD_DEFAULT, "ameoto_rt_probe_leave"));
    if (!probe_enter || !probe_leave) probe_enter = probe_leave = nullptr;
}

}  // namespace ameoto::rt
