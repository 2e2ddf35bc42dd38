// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// --host and --port, the options every subcommand shares, over an OptionReader loop.
//
// Interface:
//   TargetOptions target(environment);                 // starts from AMEOTO_HOST / AMEOTO_PORT
//   while (r.next_option()) {
//       if (target.take(r, error)) { if (!error.empty()) usage error; continue; }
//       ...the subcommand's own options...
//   }
//   if (auto e = target.finish()) usage error;         // a bad variable that no option replaced
//   target.target();                                   // where to send

#include <optional>
#include <string>

#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/target.hpp"

namespace ameoto::client {

class TargetOptions {
public:
    explicit TargetOptions(const Environment& environment);
    // True when r's current option is --host or --port (its value then read and checked; error
    // set when it is bad); false for any other option, with nothing consumed.
    bool take(OptionReader& r, std::string& error);
    std::optional<std::string> finish() const;
    const Target& target() const { return target_; }

private:
    TargetDefaults defaults_;
    Target target_;
    bool host_given_ = false, port_given_ = false;
};

}  // namespace ameoto::client
