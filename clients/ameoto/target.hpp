// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Where the server is: --host and --port, with AMEOTO_HOST and AMEOTO_PORT as defaults so a
// shell session can point every command at another server once.
//
// Interface:
//   Target t = default_target(process_environment());   // env, else 127.0.0.1:7770
//   if (auto error = set_port(t, "7771", "--port")) usage error (exit 2)
//   t.host = "studio.local";
//   t.describe();                                        // "127.0.0.1:7770", "[::1]:7770"
//
// Precedence: command-line option, then environment variable, then the protocol's default
// (UDP 7770 on 127.0.0.1, /work/shared/design/protocol-core.md). A bad AMEOTO_PORT is a usage
// error naming the variable, not a silent fallback: the user set it for a reason. A variable set
// to the empty string counts as unset (`AMEOTO_HOST= ameoto status`).

#include <functional>
#include <optional>
#include <string>

namespace ameoto::client {

constexpr const char* default_host = "127.0.0.1";
constexpr int default_port = 7770;

// name -> value, nullopt when unset; tests pass their own.
using Environment = std::function<std::optional<std::string>(const std::string& name)>;
Environment process_environment();

struct Target {
    std::string host = default_host;
    int port = default_port;
    std::string describe() const;
};

struct TargetDefaults {
    Target target;
    std::string host_error;   // a bad AMEOTO_HOST; matters only if --host does not replace it
    std::string port_error;   // a bad AMEOTO_PORT; matters only if --port does not replace it
};
TargetDefaults default_target(const Environment& environment);

// Sets t.port from text (1..65535). Returns an error naming `source` ("--port", "AMEOTO_PORT").
std::optional<std::string> set_port(Target& t, const std::string& text, const std::string& source);
std::optional<std::string> set_host(Target& t, const std::string& text, const std::string& source);

}  // namespace ameoto::client
