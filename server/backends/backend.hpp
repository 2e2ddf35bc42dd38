// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the daemon needs of an audio backend. Both backends drive the same AudioBridge::process.
//
// Interface:
//   backend->start(bridge)      // begins calling bridge.process from its audio thread
//   backend->stop()             // returns once the audio thread will not call process again
//   backend->xruns()            // blocks that missed their deadline (JACK xruns, null overruns)
//   backend->running()          // the audio cycle is advancing (for READY=1 and the watchdog)

#include <cstdint>
#include <string>

namespace ameoto {

class AudioBridge;

class Backend {
public:
    virtual ~Backend() = default;
    virtual void start(AudioBridge& bridge) = 0;
    virtual void stop() = 0;
    virtual std::uint64_t xruns() const = 0;
    virtual std::string name() const = 0;
    virtual double sample_rate() const = 0;
    virtual int block_size() const = 0;
};

}  // namespace ameoto
