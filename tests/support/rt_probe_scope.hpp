// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// For engine tests: audit a piece of code with the real-time probe (tests/support/rt_interposer.cpp),
// without the server's rt::Scope (engine/ must not depend on server/).
//
// Interface:
//   RtAudit audit;                       // resets the probe's counters
//   { RtAudit::Scope s; net.step(); }    // calls inside are counted
//   CHECK(audit.violations() == 0);      // audit.first() names the first offending function
//   CHECK(audit.entries() > 0);          // the probe really ran

#include <string>

extern "C" {
void ameoto_rt_probe_enter();
void ameoto_rt_probe_leave();
unsigned long ameoto_rt_probe_violations();
unsigned long ameoto_rt_probe_entries();
const char* ameoto_rt_probe_first_violation();
void ameoto_rt_probe_reset();
}

namespace ameoto::test {

class RtAudit {
public:
    RtAudit() { ameoto_rt_probe_reset(); }
    unsigned long violations() const { return ameoto_rt_probe_violations(); }
    unsigned long entries() const { return ameoto_rt_probe_entries(); }
    std::string first() const { return ameoto_rt_probe_first_violation(); }

    struct Scope {
        Scope() { ameoto_rt_probe_enter(); }
        ~Scope() { ameoto_rt_probe_leave(); }
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;
    };
};

}  // namespace ameoto::test
