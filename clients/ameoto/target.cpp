// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/target.hpp"

#include <charconv>
#include <cstdlib>

namespace ameoto::client {

Environment process_environment() {
    return [](const std::string& name) -> std::optional<std::string> {
        const char* value = std::getenv(name.c_str());
        if (!value) return std::nullopt;
        return std::string(value);
    };
}

std::string Target::describe() const {
    // An IPv6 literal needs brackets, or its colons run into the port's.
    const bool ipv6 = host.find(':') != std::string::npos;
    return (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

std::optional<std::string> set_port(Target& t, const std::string& text, const std::string& source) {
    int port = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), port);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || port < 1 || port > 65535)
        return source + " needs a UDP port number 1..65535, got '" + text + "'";
    t.port = port;
    return std::nullopt;
}

std::optional<std::string> set_host(Target& t, const std::string& text, const std::string& source) {
    if (text.empty()) return source + " needs a host name or IP address";
    t.host = text;
    return std::nullopt;
}

TargetDefaults default_target(const Environment& environment) {
    TargetDefaults d;
    if (auto host = environment("AMEOTO_HOST"); host && !host->empty()) {
        if (auto error = set_host(d.target, *host, "AMEOTO_HOST")) d.host_error = *error;
    }
    if (auto port = environment("AMEOTO_PORT"); port && !port->empty()) {
        if (auto error = set_port(d.target, *port, "AMEOTO_PORT")) d.port_error = *error;
    }
    return d;
}

}  // namespace ameoto::client
