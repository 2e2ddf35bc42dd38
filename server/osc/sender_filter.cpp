// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/osc/sender_filter.hpp"

#include <charconv>

namespace ameoto {

namespace {
std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t");
    if (first == std::string::npos) return "";
    return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}
}  // namespace

std::optional<SenderFilter::Network> SenderFilter::parse_network(const std::string& text, std::string& error) {
    const auto slash = text.find('/');
    const std::string address_text = text.substr(0, slash);
    boost::system::error_code ec;
    const auto address = boost::asio::ip::make_address(address_text, ec);
    if (ec || address_text.find('%') != std::string::npos) {   // no scope ids: a network is not a link
        error = "'" + text + "' is not an IPv4 or IPv6 network (ADDRESS/PREFIX, e.g. 10.0.0.0/8 or ::1/128)";
        return std::nullopt;
    }
    Network n;
    n.v6 = address.is_v6();
    const int bits = n.v6 ? 128 : 32;
    n.prefix = bits;
    if (slash != std::string::npos) {
        const std::string p = text.substr(slash + 1);
        int value = -1;
        const auto r = std::from_chars(p.data(), p.data() + p.size(), value);
        if (p.empty() || r.ec != std::errc() || r.ptr != p.data() + p.size() || value < 0 || value > bits) {
            error = "'" + text + "': the prefix length must be 0.." + std::to_string(bits);
            return std::nullopt;
        }
        n.prefix = value;
    }
    if (n.v6) {
        const auto b = address.to_v6().to_bytes();
        std::copy(b.begin(), b.end(), n.bytes.begin());
    } else {
        const auto b = address.to_v4().to_bytes();
        std::copy(b.begin(), b.end(), n.bytes.begin());
    }
    // Host bits set below the prefix: refused, so 10.1.0.0/8 is not silently read as 10.0.0.0/8.
    Network masked = n;
    for (int bit = n.prefix; bit < bits; ++bit) masked.bytes[static_cast<std::size_t>(bit / 8)] &= static_cast<unsigned char>(~(0x80u >> (bit % 8)));
    if (masked.bytes != n.bytes) {
        error = "'" + text + "' has host bits set below the /" + std::to_string(n.prefix) + " prefix";
        return std::nullopt;
    }
    return n;
}

std::optional<SenderFilter> SenderFilter::parse(const std::string& list, std::string& error) {
    SenderFilter filter;
    std::size_t start = 0;
    for (;;) {
        const auto comma = list.find(',', start);
        const std::string item = trimmed(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (item.empty()) {
            error = "an empty network in '" + list + "' (networks are separated by single commas)";
            return std::nullopt;
        }
        auto n = parse_network(item, error);
        if (!n) return std::nullopt;
        filter.networks_.push_back(*n);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return filter;
}

bool SenderFilter::matches(const Network& n, const unsigned char* bytes, bool v6) {
    if (n.v6 != v6) return false;
    const int whole = n.prefix / 8;
    for (int i = 0; i < whole; ++i)
        if (n.bytes[static_cast<std::size_t>(i)] != bytes[i]) return false;
    const int rest = n.prefix % 8;
    if (rest == 0) return true;
    const auto mask = static_cast<unsigned char>(0xFFu << (8 - rest));
    return (n.bytes[static_cast<std::size_t>(whole)] & mask) == (bytes[whole] & mask);
}

bool SenderFilter::allows(const boost::asio::ip::address& sender) const {
    if (networks_.empty()) return true;
    bool v6 = sender.is_v6();
    std::array<unsigned char, 16> bytes{};
    if (v6 && sender.to_v6().is_v4_mapped()) v6 = false;   // an IPv4 client on a dual-stack socket
    if (v6) {
        const auto b = sender.to_v6().to_bytes();
        std::copy(b.begin(), b.end(), bytes.begin());
    } else {
        const auto v4 = sender.is_v4() ? sender.to_v4() : boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, sender.to_v6());
        const auto b = v4.to_bytes();
        std::copy(b.begin(), b.end(), bytes.begin());
    }
    for (const Network& n : networks_)
        if (matches(n, bytes.data(), v6)) return true;
    return false;
}

std::string SenderFilter::text() const {
    std::string out;
    for (const Network& n : networks_) {
        if (!out.empty()) out += ',';
        if (n.v6) {
            boost::asio::ip::address_v6::bytes_type b;
            std::copy(n.bytes.begin(), n.bytes.end(), b.begin());
            out += boost::asio::ip::address_v6(b).to_string();
        } else {
            out += boost::asio::ip::address_v4({n.bytes[0], n.bytes[1], n.bytes[2], n.bytes[3]}).to_string();
        }
        out += "/" + std::to_string(n.prefix);
    }
    return out;
}

}  // namespace ameoto
