// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Marks the code the audio thread runs, so a test can prove it never allocates, frees, locks,
// blocks or logs.
//
// Interface:
//   { rt::Scope scope; ... audio work ... }   // everything inside is audited when a probe is loaded
//
// In production no probe is loaded and a Scope costs two predictable branches on null pointers.
// The probe is tests/support/rt_interposer.cpp: it replaces malloc, free, pthread_mutex_lock, write,
// nanosleep and their kin, and counts every call made inside a Scope. It is linked into the unit tests
// and LD_PRELOADed into ameotod by the integration test; Scope finds it by name at start-up
// (dlsym of ameoto_rt_probe_enter / ameoto_rt_probe_leave), so the daemon links nothing of it.

namespace ameoto::rt {

void init_probe();   // call once at start-up, off the audio thread (dlsym may allocate)

extern void (*probe_enter)();
extern void (*probe_leave)();

struct Scope {
    Scope() {
        if (probe_enter) probe_enter();
    }
    ~Scope() {
        if (probe_leave) probe_leave();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
};

}  // namespace ameoto::rt
