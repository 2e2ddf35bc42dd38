// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/target_options.hpp"

namespace ameoto::client {

TargetOptions::TargetOptions(const Environment& environment)
    : defaults_(default_target(environment)), target_(defaults_.target) {}

bool TargetOptions::take(OptionReader& r, std::string& error) {
    const bool host = r.is("--host");
    if (!host && !r.is("--port")) return false;
    const auto value = r.value();
    if (!value) {
        error = r.error();
        return true;
    }
    const auto problem = host ? set_host(target_, *value, "--host") : set_port(target_, *value, "--port");
    if (problem) error = *problem;
    (host ? host_given_ : port_given_) = true;
    return true;
}

std::optional<std::string> TargetOptions::finish() const {
    if (!host_given_ && !defaults_.host_error.empty()) return defaults_.host_error;
    if (!port_given_ && !defaults_.port_error.empty()) return defaults_.port_error;
    return std::nullopt;
}

}  // namespace ameoto::client
