// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Which datagrams a flooded server answers ahead of the others: /status, /version, and any address
// asked with no value (/rain/rate, /notify ...). Decided by peeking at the address and the type tags
// only, so that it costs next to nothing for each datagram of a flood.
//
// Interface:
//   bool cheap = is_cheap_query(bytes, size);
//   bool status = is_status_request(bytes, size);   // exactly /status with no arguments
//
// A well-formed OSC message (not a bundle) with an empty type tag string whose address the table
// answers at once when sent with no value (/status, /version, /surfaces, every query form without a
// name). Anything else, or anything malformed, is not cheap: it waits its turn and is decoded,
// validated (and refused, if need be) then.

#include <cstddef>

namespace ameoto {

bool is_cheap_query(const unsigned char* data, std::size_t size);
bool is_status_request(const unsigned char* data, std::size_t size);

}  // namespace ameoto
