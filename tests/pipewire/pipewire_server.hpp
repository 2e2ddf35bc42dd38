// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A private, headless PipeWire server for a test: its own runtime folder, no D-Bus, no session manager,
// one null sink with JACK ports, a fixed quantum. JACK clients reach it through `pw-jack`.
//
// Interface:
//   std::vector<std::string> absent = PipeWireServer::missing_programs();   // "pw-jack (pipewire-jack)", ...
//   PipeWireServer pw;                 // starts `pipewire`, forces 48 kHz / 1024 frames, makes the sink;
//                                      // throws std::runtime_error with pipewire's output if it does not come up
//   ChildProcess p(pw.jack_argv({"jack_lsp"}), pw.env(), pw.child_options());   // {"pw-jack", "jack_lsp"}
//   pw.sink()                          // "ameoto_sink": ports ameoto_sink:playback_FL/FR (physical
//                                      // inputs, what --autoconnect finds) and ameoto_sink:monitor_FL/FR
//   ~PipeWireServer                    // SIGTERM to pipewire by its PID, then removes the runtime folder
//
// Why each setting (../shared/design/netjack2.md, "PipeWire's JACK, headless", tried on Debian 12 with
// PipeWire 0.3.65):
// - XDG_RUNTIME_DIR and PIPEWIRE_RUNTIME_DIR name a fresh 0700 folder: the server's socket
//   (pipewire-0) is made there, so a desktop's own PipeWire is never reached, nor needed (a CI box has
//   no runtime folder at all). XDG_CONFIG_HOME points there too, so a user's ~/.config/pipewire
//   (a jack.conf with another quantum, say) does not change the test.
// - DBUS_SESSION_BUS_ADDRESS and DISPLAY are dropped: pipewire logs that it has no session bus (its
//   portal and RTKit modules) and runs on.
// - No session manager: nothing links ports by itself; ameotod's --autoconnect and jack_connect make
//   every link. The null sink is made with pw-cli and given its ports with a PortConfig in DSP mode
//   (one F32 port per channel, plus monitor ports), which is what WirePlumber would do.
// - clock.force-quantum 1024 and clock.force-rate 48000 (the "settings" metadata) fix the graph's period
//   and rate: otherwise the quantum follows the clients' requested latency (1024 by default).

#include <memory>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/temp_dir.hpp"

namespace ameoto::test {

class PipeWireServer {
public:
    static constexpr int kRate = 48000;
    // PipeWire's default quantum (21.3 ms). At 256 frames (5.3 ms) this 2-CPU VM's stalls of about 6 ms
    // (its kernel runs preempt=none; docs/bench-realtime.md) pushed ameotod's callback past the period in
    // about one 3 s take in four, with its mean load at 10 %; each such cycle is lost from the recording.
    static constexpr int kQuantum = 1024;

    static std::vector<std::string> missing_programs();

    PipeWireServer();
    ~PipeWireServer();
    PipeWireServer(const PipeWireServer&) = delete;
    PipeWireServer& operator=(const PipeWireServer&) = delete;

    std::vector<std::string> env(const std::vector<std::string>& more = {}) const;
    ChildOptions child_options() const;
    std::vector<std::string> jack_argv(std::vector<std::string> argv) const;
    std::string sink() const { return "ameoto_sink"; }
    // What pipewire printed so far (for a failure's message).
    std::string log();

private:
    // Runs a PipeWire tool against this server; throws with its output when it fails.
    void run_tool(const std::vector<std::string>& argv, const std::string& what);

    TempDir runtime_{"ameoto-pipewire"};
    std::unique_ptr<ChildProcess> process_;
};

}  // namespace ameoto::test
