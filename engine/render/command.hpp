// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The small, trivially copyable messages that cross between the control thread and the audio thread.
//
// Command: control -> audio, already validated and in SI units (protocol/ does that).
// RendererEvent: audio -> control, for replies the audio thread decides (/synced, /fail busy).
// Both are plain data so a fixed-capacity lock-free queue can carry them without allocation.

#include <cstdint>
#include <type_traits>

namespace ameoto {

enum class CommandKind : std::uint8_t {
    drop,        // values: diameter m, speed m/s (0 = terminal), x m, y m
    rain_rate,   // values[0]: rain rate, mm/h (the one non-SI field: the rain statistics are written in it)
    sync,        // id: reply /synced id once applied
    swap_surface,  // object: an UmbrellaScene (new surface material) built off the audio thread; the old
                   // scene rings out, then returns in a `retired` event
    swap_liquid,   // object: an UmbrellaScene (new liquid), the same way
    lod,           // values[0]: budget, fraction of the block period; values[1]: most lattice drops at once
    load_scene,    // object: a LoadedScene (render/loaded_scene.hpp) built off the audio thread
    wind,          // values: speed m/s, direction rad (toward, counter-clockwise from +x), gustiness 0..1
    listener,      // values: x, y, z m, facing rad (the umbrella, if any, is held: it moves along)
    gain,          // values[0]: the listening gain, dB (output_stage.hpp); ramps over 50 ms
    level,         // values[0]: the scene's level gain, dB (--level auto's choice, moved by /loudness); ramps
    orientation,   // values: yaw, pitch, roll rad (/listener/orientation); object: the AmbixRotation of the
                   // bus (models/ambisonics.hpp) built off the audio thread, returned in a `retired` event;
                   // the bus turns to it over rotation_ramp_frames (renderer.hpp)
};

struct Command {
    CommandKind kind = CommandKind::sync;
    bool timed = false;          // true: apply at `frame` (a bundle's timetag); false: as soon as possible
    std::uint16_t reply_to = 0;  // index of the sender in the control thread's client table
    std::int32_t id = 0;
    std::uint64_t frame = 0;     // sample time at which to apply it, when timed
    double values[4] = {0, 0, 0, 0};
    void* object = nullptr;      // swap_surface, swap_liquid, load_scene, orientation: ownership passes to the renderer
};

enum class RendererEventKind : std::uint8_t {
    synced,     // a /sync was reached: reply /synced id
    busy,       // a command could not be scheduled (the pending list was full): reply /fail busy
    swapped,    // a swap_surface or swap_liquid took effect: reply /done
    retired,    // object (of object_type) the audio thread no longer uses; the control thread deletes it
};

// What a retired event's object is, so the control thread deletes it as its type.
enum class RetiredObject : std::uint8_t { none, umbrella_scene, scene_surfaces, loaded_scene, rotation };

struct RendererEvent {
    RendererEventKind kind = RendererEventKind::synced;
    CommandKind command = CommandKind::sync;
    std::uint16_t reply_to = 0;
    std::int32_t id = 0;
    void* object = nullptr;
    RetiredObject object_type = RetiredObject::none;
};

static_assert(std::is_trivially_copyable_v<Command>);
static_assert(std::is_trivially_copyable_v<RendererEvent>);

}  // namespace ameoto
