// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The refusal message for a value out of its range, shared by the models' validators.
//
// Interface:
//   std::string why = out_of_range("thickness", h, 1e-5, 0.05, "m", "too thin to hold", "no longer thin");
//   if (!why.empty()) throw std::invalid_argument(why);
//
// Empty when low <= value <= high (and finite); otherwise "WHAT VALUE UNIT is outside LOW .. HIGH UNIT:
// REASON", with `below` as the reason for a value under the range or not finite, `above` over it.

#include <cmath>
#include <sstream>
#include <string>

namespace ameoto {

inline std::string out_of_range(const char* what, double value, double low, double high, const char* unit, const char* below,
                                const char* above) {
    if (std::isfinite(value) && value >= low && value <= high) return {};
    std::ostringstream s;
    s << what << " " << value << " " << unit << " is outside " << low << " .. " << high << " " << unit << ": "
      << (std::isfinite(value) && value > high ? above : below);
    return s.str();
}

}  // namespace ameoto
