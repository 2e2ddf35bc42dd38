// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/expected_reply.hpp"

#include "protocol/address_table.hpp"

namespace ameoto::client {

std::optional<std::string> expected_reply(const std::string& address) {
    // The protocol table says what each address answers ("/done /quit (...)" -> "/done"): one source.
    const protocol::AddressSpec* spec = protocol::find_address(address);
    if (!spec || !*spec->reply) return std::nullopt;
    const std::string reply = spec->reply;
    return reply.substr(0, reply.find(' '));
}

bool ends_wait(const std::string& sent_address, const std::vector<protocol::OscArgument>& sent_arguments,
               const protocol::DecodedMessage& reply) {
    const auto& args = reply.args;
    const bool first_is_text = !args.empty() && (args[0].type == 's' || args[0].type == 'S');
    if (reply.address == "/fail") return first_is_text && args[0].text == sent_address;
    // A query (ADDRESS with no value, or only a name) is answered ADDRESS.reply; so are /status and /version.
    if (reply.address == sent_address + ".reply") return true;
    const auto expected = expected_reply(sent_address);
    if (!expected || reply.address != *expected) return false;
    if (sent_address == "/sync") {
        // Another /sync from the same socket cannot be in flight, but an id that does not match is
        // not ours to end on either.
        return !args.empty() && args[0].is_number() && !sent_arguments.empty() && sent_arguments[0].is_number() &&
               args[0].number == sent_arguments[0].number;
    }
    // /done names what it answers (/quit, /material/surface, ...): only our own ends the wait.
    if (*expected == "/done") return first_is_text && args[0].text == sent_address;
    return true;
}

}  // namespace ameoto::client
