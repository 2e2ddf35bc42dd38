// SPDX-License-Identifier: GPL-3.0-or-later
// /nodes in the address table: no arguments, the nodes action (this node and its --peers); any argument
// is refused with a reason; /nodes.reply is no request.
#include <doctest/doctest.h>

#include <string>

#include "protocol/address_table.hpp"

namespace ameoto::protocol {

TEST_CASE("/nodes: no arguments asks for the nodes; an argument is refused; /nodes.reply is no request") {
    DecodedMessage m;
    m.address = "/nodes";
    Validation v = validate(m, ProtocolContext{});
    REQUIRE(v.ok);
    CHECK(v.request.action == Action::nodes);
    m.args = {OscArgument::from_int(1)};
    m.types = "i";
    v = validate(m, ProtocolContext{});
    CHECK_FALSE(v.ok);
    CHECK(v.reason.find("too many") != std::string::npos);
    CHECK_FALSE(find_address("/nodes.reply"));
}

}  // namespace ameoto::protocol
