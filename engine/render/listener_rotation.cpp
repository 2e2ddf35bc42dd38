// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/listener_rotation.hpp"

#include <cmath>

namespace ameoto {

void FacingTurn::reset(int order, double facing_rad) {
    order_ = order;
    for (int m = 1; m < degrees; ++m) {
        c_to_[m] = c_from_[m] = c_[m] = std::cos(m * facing_rad);
        s_to_[m] = s_from_[m] = s_[m] = std::sin(m * facing_rad);
    }
    facing_ = facing_rad;
    left_ = 0;
    active_ = facing_rad != 0.0;
}

void FacingTurn::turn_to(double facing_rad) {
    if (left_ == 0 && facing_rad == facing_) return;
    facing_ = facing_rad;
    // From the blend reached now (c_, s_ are this sample's, or the target's at rest).
    for (int m = 1; m < degrees; ++m) {
        c_from_[m] = c_[m];
        s_from_[m] = s_[m];
        c_to_[m] = std::cos(m * facing_rad);
        s_to_[m] = std::sin(m * facing_rad);
    }
    left_ = glide_frames;
    active_ = true;
}

void FacingTurn::step() {
    if (left_ == 0) return;
    const double t = 1.0 - static_cast<double>(--left_) / glide_frames;
    for (int m = 1; m < degrees; ++m) {
        c_[m] = (1.0 - t) * c_from_[m] + t * c_to_[m];
        s_[m] = (1.0 - t) * s_from_[m] + t * s_to_[m];
    }
    if (left_ == 0) {   // at rest: exactly the target; back to the encoder's samples at facing 0
        bool identity = true;
        for (int m = 1; m < degrees; ++m) {
            c_[m] = c_to_[m];
            s_[m] = s_to_[m];
            identity = identity && c_[m] == 1.0 && s_[m] == 0.0;
        }
        active_ = !identity;
    }
}

void FacingTurn::add_turned(const float* in, float* out) const {
    for (int n = 0; n <= order_; ++n) {
        const int centre = n * n + n;   // ACN of degree 0
        out[centre] += in[centre];
        for (int m = 1; m <= n; ++m) {
            const double cosine = in[centre + m], sine = in[centre - m];
            out[centre + m] += static_cast<float>(c_[m] * cosine + s_[m] * sine);
            out[centre - m] += static_cast<float>(c_[m] * sine - s_[m] * cosine);
        }
    }
}

}  // namespace ameoto
