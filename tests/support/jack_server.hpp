// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A private JACK server for a test: jackd2 with the dummy driver, no real-time, 48 kHz, 256 frames.
//
// Interface:
//   JackServer jack;                  // starts jackd under a unique server name, waits with jack_wait;
//                                     // throws std::runtime_error with jackd's output if it does not come up
//   JackServer jack(true);            // --realtime: its clients' process threads at SCHED_FIFO where the
//                                     // user may (root, an rtprio limit); jackd carries on without otherwise
//   ChildProcess p(argv, jack.env()); // JACK_DEFAULT_SERVER=<its name>: clients find this server only
//   jack.stop(); jack.start();        // a crash and a return, for reconnection tests
//   jack.kill();                      // SIGKILL: a crash without jackd's own clean-up
//   jack.output();                    // jackd's log so far (its xruns, a netmanager's lost packets)
//   ~JackServer                       // stops jackd by its PID and removes the /dev/shm files it left
//
// Its own server name means a JACK server the user runs is never touched, and tests can run side by side.

#include <memory>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"

namespace ameoto::test {

class JackServer {
public:
    explicit JackServer(bool realtime = false);
    ~JackServer();
    JackServer(const JackServer&) = delete;
    JackServer& operator=(const JackServer&) = delete;

    void start();
    void stop();
    void kill();
    const std::string& name() const { return name_; }
    const std::string& output();   // what jackd printed so far (never blocks; empty once stopped)
    std::vector<std::string> env(const std::vector<std::string>& more = {}) const;

private:
    std::string name_;
    bool realtime_ = false;
    std::unique_ptr<ChildProcess> process_;
};

}  // namespace ameoto::test
