// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/osc/cheap_query.hpp"

#include <cstring>
#include <set>
#include <string>

#include "protocol/address_table.hpp"

namespace ameoto {

namespace {

// The length of the OSC string at `data` including its padding (OSC 1.0: 1-4 NULs to a multiple of
// 4), or 0 when it does not end within `size`.
std::size_t padded_string_length(const unsigned char* data, std::size_t size) {
    const void* nul = std::memchr(data, 0, size);
    if (!nul) return 0;
    const auto length = static_cast<std::size_t>(static_cast<const unsigned char*>(nul) - data);
    const std::size_t padded = (length / 4 + 1) * 4;
    return padded <= size ? padded : 0;
}

// The addresses that, sent with no value, the table answers at once (status, version, a query),
// found by validating each one so: a new address joins by its table row alone.
const std::set<std::string>& answered_with_no_value() {
    static const std::set<std::string> addresses = [] {
        std::set<std::string> found;
        const protocol::ProtocolContext context;
        for (const protocol::AddressSpec& spec : protocol::address_table()) {
            protocol::DecodedMessage message;
            message.address = spec.address;
            const protocol::Validation v = protocol::validate(message, context);
            using protocol::Action;
            if (v.ok && (v.request.action == Action::status || v.request.action == Action::version || v.request.action == Action::query))
                found.insert(spec.address);
        }
        return found;
    }();
    return addresses;
}

}  // namespace

bool is_cheap_query(const unsigned char* data, std::size_t size) {
    if (size < 8 || size % 4 != 0 || data[0] != '/') return false;
    const std::size_t address_length = padded_string_length(data, size);
    if (address_length == 0) return false;
    // The type tag string must be exactly "," (no arguments) and end the message.
    if (size != address_length + 4 || std::memcmp(data + address_length, ",\0\0\0", 4) != 0) return false;
    return answered_with_no_value().count(reinterpret_cast<const char*>(data)) > 0;
}

bool is_status_request(const unsigned char* data, std::size_t size) {
    static constexpr unsigned char status[] = {'/', 's', 't', 'a', 't', 'u', 's', 0, ',', 0, 0, 0};
    return size == sizeof status && std::memcmp(data, status, sizeof status) == 0;
}

}  // namespace ameoto
