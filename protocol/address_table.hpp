// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The OSC address space as a table: every address, its arguments with units and ranges, and what it
// turns into. docs/PROTOCOL.md documents the same table; tests walk it so no address escapes
// validation.
//
// Interface:
//   ProtocolContext ctx{...};                            // what validation must know of the scene
//   Validation v = validate(message, ctx);               // pure: no I/O, no state change
//   if (!v.ok) reply /fail message.address v.reason;     // nothing changes
//   else act on v.request (queue v.request.command, answer /status, quit, ...)
//   for (const AddressSpec& a : address_table()) ...     // the whole space, for docs and tests
//   a.query.available                                   // ADDRESS with no value is a query (Action::query)
//
// Conventions (scsynth's, where users expect them): numbers may be sent as i, h, f or d and are
// coerced; NaN and Inf are refused; a value outside its range is refused, never clamped; missing
// and extra arguments are refused. Units at the boundary are the ones musicians use (mm, mm/h,
// m/s, m); the Command carries SI (except the rain rate, see engine/render/command.hpp).

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/models/liquid.hpp"
#include "engine/models/membrane.hpp"
#include "engine/render/command.hpp"
#include "engine/scene/scene_description.hpp"
#include "protocol/osc_codec.hpp"

namespace ameoto::protocol {

enum class ArgumentKind { number, integer, text };

struct ArgumentSpec {
    const char* name;
    ArgumentKind kind;
    const char* unit;          // "" when unitless
    double min = 0.0, max = 0.0;
    bool optional = false;
    const char* help = "";
    const char* example = "";  // a valid value, for docs and the tests that walk the table
};

enum class Action {
    enqueue,   // send `command` to the audio thread
    status,    // reply /status.reply now
    quit,      // reply /done /quit and stop
    set_liquid,             // build the drops' liquid off the audio thread, then swap it in
    set_surface_material,   // build the surface in that material off the audio thread, then swap it in
    load_scene,             // resolve `scene_name` (built in, or a file in the scene folder), build, swap in
    save_scene,             // write the current scene as `scene_name` into the scene folder, atomically
    edit_scene,             // change the current scene (`edit`) and rebuild it off the audio thread
    query,                  // reply ADDRESS.reply with the value now in effect (`query_address`, `query_text`)
    notify,                 // subscribe (`notify_on`) or unsubscribe the sender: periodic /status.reply and /meter
    version,                // reply /version.reply
    reply_port,             // send this sender's later replies to its IP address at `reply_port` (0: its own port)
    set_loudness,           // --level auto's target for each scene's default rain (`loudness_lufs`)
    nodes,                  // reply /nodes.reply: this node and its --peers (server/peers.hpp)
    on_block,               // /nodes/block: the packet's timed commands go on the start of the nearest audio block
};

// The protocol's own version, in /version.reply: raised when an address or a reply changes shape.
// 1: the core (rate, drop, scenes, materials, status, sync, quit); 2: /scene, /notify + /meter,
// /version, queries (ADDRESS with no value -> ADDRESS.reply), OSC over TCP.
inline constexpr int protocol_version = 2;

// The query form of a settable address: the address with no value (or, for addresses that set one of
// several things, with only the argument that names it) replies ADDRESS.reply with what is in effect.
struct QuerySpec {
    bool available = false;
    std::vector<ArgumentSpec> arguments;   // what names the thing asked about (e.g. a surface); usually none
    const char* reply = "";                // the reply's type tags and fields, for docs
};

// A change to the current scene that needs a rebuild: the drop size distribution, or a surface.
struct SceneEdit {
    enum class Op { dsd, surface_add, surface_set, surface_remove, accuracy, air, impact } op = Op::dsd;
    std::string dsd;                 // dsd: its name
    double mu = 2.0, lambda = 0.0;   // dsd gamma: shape, 1/mm (0: from the rate)
    SurfaceDescription surface;      // surface_add / surface_set (all fields); surface_remove: its name
    std::optional<AccuracyBudget> accuracy;   // accuracy: the new budget (none: the default method)
    bool air = false;                // air: every umbrella's canopy in air (true) or in vacuum
    ImpactModel impact = ImpactModel::wet;   // impact: how drops meet every umbrella's canopy
};

struct Request {
    Action action = Action::enqueue;
    Command command{};
    std::optional<Liquid> liquid;              // set_liquid
    std::string surface;                       // set_surface_material
    std::optional<MembraneMaterial> material;  // set_surface_material
    std::string scene_name;                    // load_scene, save_scene: a name, never a path
    SceneEdit edit;                            // edit_scene
    std::string query_address;                 // query: the address asked about (its reply is ADDRESS.reply)
    std::string query_text;                    // query: its text argument when it takes one (a surface's name)
    bool notify_on = false;                    // notify
    int reply_port = 0;                        // reply_port: 1..65535, or 0 for the sender's own port
    double loudness_lufs = -23.0;              // set_loudness
};

struct Validation {
    bool ok = false;
    Request request;
    std::string reason;        // for /fail when !ok
};

struct ProtocolContext {
    std::vector<std::string> surfaces{"umbrella"};
    // Custom liquids and materials defined earlier over OSC, by name (presets are always known).
    std::function<std::optional<Liquid>(const std::string& name)> custom_liquid;
    std::function<std::optional<MembraneMaterial>(const std::string& name)> custom_material;
    // true when (x, y) in m lies on the named surface; the daemon asks the engine's geometry.
    std::function<bool(const std::string& surface, double x, double y)> on_surface;
    int ambisonic_order = 0;   // the stream's Ambisonic order (1..3; --format ambix:N), 0 for the other
                               // formats (/listener/orientation's rotation matrix is built for it)
    bool ears = false;         // --format ears: /listener/orientation is refused (two fixed ear points)
};

struct ValidatedArguments {
    std::vector<double> numbers;   // in the table's units, in order (numbers and integers)
    std::vector<std::string> texts;
};

struct AddressSpec {
    const char* address;
    std::vector<ArgumentSpec> arguments;
    const char* summary;
    const char* reply;         // what the server answers on success ("" for nothing)
    // Builds the request from arguments that already passed the table's checks; may still refuse
    // (returns a reason) for checks that need the context, such as a point off the surface.
    std::function<std::optional<std::string>(const ValidatedArguments&, const ProtocolContext&, Request&)> build;
    QuerySpec query{};         // set after the row is made, so rows written without it stay valid
};

std::span<const AddressSpec> address_table();
const AddressSpec* find_address(const std::string& address);

Validation validate(const DecodedMessage& message, const ProtocolContext& context);

// The server's replies (their exact shapes are in docs/PROTOCOL.md).
std::vector<OscArgument> fail_arguments(const std::string& address, const std::string& reason);

}  // namespace ameoto::protocol
