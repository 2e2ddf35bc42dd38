// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the audio thread's events become on the control thread: /done once a rebuilt scene, surface
// or liquid plays (for a scene load, the address that asked, in order), /synced at a /sync's sample,
// /fail busy for a command the renderer had no room to schedule, and every object the audio thread
// retired freed here, as its type, never on the audio thread.
//
// Interface:
//   AudioEvents events(bridge, replies, scenes, traffic);
//   bool freed = events.handle();   // each poll: every event waiting; true when it freed a scene
//                                   // (then return_free_memory(): memory_return.hpp)
//
// Thread: the control thread only (it is the one reader of the bridge's event queue).

#include "server/osc/traffic_counters.hpp"
#include "server/realtime/audio_bridge.hpp"
#include "server/replies.hpp"
#include "server/scene_manager.hpp"

namespace ameoto {

class AudioEvents {
public:
    AudioEvents(AudioBridge& bridge, Replies& replies, SceneManager& scenes, TrafficCounters& traffic)
        : bridge_(bridge), replies_(replies), scenes_(scenes), traffic_(traffic) {}
    bool handle();

private:
    AudioBridge& bridge_;
    Replies& replies_;
    SceneManager& scenes_;
    TrafficCounters& traffic_;
};

}  // namespace ameoto
