// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --allow: which senders may talk to ameotod, as a list of IPv4 and IPv6 networks in CIDR notation.
//
// Interface:
//   std::string error;
//   std::optional<SenderFilter> f = SenderFilter::parse("127.0.0.1/32,10.0.0.0/8,::1/128", error);
//   f->allows(boost::asio::ip::make_address("10.1.2.3"));   // true
//   f->text();                                                // "127.0.0.1/32,10.0.0.0/8,::1/128" (canonical)
//   SenderFilter{}                                            // no networks: allows everyone (no --allow)
//
// A network is ADDRESS/PREFIX (PREFIX 0..32 for IPv4, 0..128 for IPv6), or a bare ADDRESS meaning
// one host (/32 or /128). Host bits set below the prefix (10.1.0.0/8) are refused rather than masked:
// a typo there usually means the user meant another network. An IPv4 sender reaching an IPv6 socket
// arrives as an IPv4-mapped address (::ffff:a.b.c.d) and is matched as the IPv4 address it is.

#include <boost/asio/ip/address.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace ameoto {

class SenderFilter {
public:
    static std::optional<SenderFilter> parse(const std::string& list, std::string& error);

    bool allows(const boost::asio::ip::address& sender) const;
    bool restricts() const { return !networks_.empty(); }
    std::string text() const;

private:
    struct Network {
        bool v6 = false;
        std::array<unsigned char, 16> bytes{};   // IPv4 uses the first 4
        int prefix = 0;
    };
    static std::optional<Network> parse_network(const std::string& text, std::string& error);
    static bool matches(const Network& n, const unsigned char* bytes, bool v6);
    std::vector<Network> networks_;
};

}  // namespace ameoto
