// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The rows of the OSC address table (address_table.hpp), one family of addresses per file
// (address_entries_*.cpp), and the helpers they share. Internal to protocol/: the interface is
// address_table.hpp. make_table() (address_table.cpp) calls the add_* functions in the table's order,
// which is the order `ameoto send --help` and the fuzzer's corpus list the addresses in; each appends
// its rows to t. Any thread: the table is built once, on first use, and read-only afterwards.

#include <string>
#include <vector>

#include "protocol/address_table.hpp"

namespace ameoto::protocol::entries {

// A number as refusals quote it: %.10g, enough digits that 500.0001 is not shown as 500 in
// "500.0001 is outside 0..500" (address_table.cpp).
std::string format_number(double v);

// address_entries_rain.cpp
void add_rain_and_drop_entries(std::vector<AddressSpec>& t);   // /rain/rate, /drop
void add_wind_and_dsd_entries(std::vector<AddressSpec>& t);    // /rain/wind, /rain/dsd
// address_entries_scene.cpp: the scene as a whole and its edits
void add_scene_entries(std::vector<AddressSpec>& t);           // /scene, /scene/load, /scene/save
void add_surface_entries(std::vector<AddressSpec>& t);         // /surface/add, /surface/set, /surfaces, /surface/remove
void add_accuracy_entry(std::vector<AddressSpec>& t);          // /accuracy
void add_canopy_air_entry(std::vector<AddressSpec>& t);        // /canopy/air
void add_canopy_impact_entry(std::vector<AddressSpec>& t);     // /canopy/impact
// address_entries_level.cpp
void add_level_entries(std::vector<AddressSpec>& t);           // /lod, /gain, /loudness
// address_entries_material.cpp
void add_material_entries(std::vector<AddressSpec>& t);        // /material/liquid, /material/surface
// address_entries_server.cpp: the server itself, not the sound
void add_server_entries(std::vector<AddressSpec>& t);          // /status, /notify, /nodes, /nodes/block, /version, /sync, /quit
void add_reply_port_entry(std::vector<AddressSpec>& t);        // /reply/port

}  // namespace ameoto::protocol::entries
