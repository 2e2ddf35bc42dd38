// SPDX-License-Identifier: GPL-3.0-or-later
// The listener's turns on every format (renderer.hpp, "Ambisonics" and the panned formats after it;
// docs/output-formats.md, "Turning the head"): /listener's facing and /listener/orientation's head
// rotation, none of which rebuilds anything. Audio thread: no allocation.
#include <cmath>

#include "engine/core/physical_constants.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto {

// The texture bed's ring: direction v at the ring speaker's azimuth (panning.hpp's layout: the first
// at half a spacing left of front, then clockwise) and the canopy's mean elevation seen from the head.
// A loop over the canopy's nodes, no allocation (it runs on the audio thread after a scene change).
void Renderer::encode_grains(const Canopy& canopy) {
    const Vec3 head{0.0, 0.0, -config_.listener_below_m};
    double up = 0.0, out = 0.0;
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            const Vec3 d = canopy.rest_position(k, i) - head;
            up += d.z;
            out += std::hypot(d.x, d.y);
        }
    const double elevation = std::atan2(up, out), spacing = 2.0 * constants::pi / grain_ring;
    const int order = ambix_order(config_.channels);
    for (int v = 0; v < grain_ring; ++v)
        grain_encoding_[static_cast<std::size_t>(v)] = ambix_gains(spacing / 2.0 - v * spacing, elevation, order);
}

// The head turned (/listener/orientation). Ambisonics: the bus glides from where it is now to the new
// rotation. The panned formats: every direction is turned by the new H^T and re-panned, the gains
// gliding (the command's angles give H: head_rotation is a few products, no allocation); the matrix the
// command carries (order 0 there) only goes back. Ears: nothing turns (the protocol refuses it there;
// turning the surfaces without the two ear points under the umbrella would split the scene).
void Renderer::set_orientation(const Command& c) {
    auto* target = static_cast<AmbixRotation*>(c.object);
    const bool ears = config_.listener == ListenerStyle::ears && config_.channels == 2;
    if (!ambisonic() && !ears) {
        head_ = head_rotation(c.values[0], c.values[1], c.values[2]);
        head_turned_ = head_ != std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1};
        surfaces_->set_head(head_);
        if (fading_surfaces_) fading_surfaces_->set_head(head_);
        scene_->drops.turn_head(head_, rotation_ramp_frames);
        if (fading_) fading_->drops.turn_head(head_, rotation_ramp_frames);
    }
    if (!target) return;
    if (ambisonic() && target->order == rotation_to_.order) {
        // Mid-turn, the glide starts again from the matrix it had reached (the crossfade's weights
        // applied to the matrices), so a stream of tracker updates never jumps.
        if (rotation_ramp_left_ > 0) {
            const double t = 1.0 - static_cast<double>(rotation_ramp_left_) / rotation_ramp_frames;
            for (std::size_t i = 0; i < rotation_from_.m.size(); ++i)
                rotation_from_.m[i] = (1.0 - t) * rotation_from_.m[i] + t * rotation_to_.m[i];
        } else {
            rotation_from_ = rotation_to_;
        }
        rotation_to_ = *target;
        rotation_ramp_left_ = rotation_ramp_frames;
        rotating_ = true;
    }
    if (retire(target, RetiredObject::rotation)) return;
    for (AmbixRotation*& slot : unreturned_)
        if (!slot) {
            slot = target;
            return;
        }
    // Every slot taken and the event list full: the control thread has stopped reading; the object
    // stays with the command's owner (the destructor frees the slots, never the audio thread).
}

void Renderer::rotate(float* frame) {
    double in[max_ambix_channels] = {}, to[max_ambix_channels] = {};
    const int channels = config_.channels;
    for (int ch = 0; ch < channels; ++ch) in[ch] = frame[ch];
    rotation_to_.apply(in, to);
    if (rotation_ramp_left_ > 0) {
        double from[max_ambix_channels] = {};
        rotation_from_.apply(in, from);
        const double t = 1.0 - static_cast<double>(--rotation_ramp_left_) / rotation_ramp_frames;
        for (int ch = 0; ch < channels; ++ch) frame[ch] = static_cast<float>((1.0 - t) * from[ch] + t * to[ch]);
        if (rotation_ramp_left_ == 0 && rotation_to_.is_identity()) rotating_ = false;   // back at rest: the encoder's samples
        return;
    }
    for (int ch = 0; ch < channels; ++ch) frame[ch] = static_cast<float>(to[ch]);
}

// /listener: the umbrella is held by the listener, so it moves and turns along; only the other surfaces'
// paths change (they glide there, propagation.hpp). On an Ambisonic stream the facing turns the world
// bus (the surfaces encode in the scene's frame); on the others the surfaces re-pan, gliding.
void Renderer::move_listener(const Command& c) {
    surfaces_->set_listener(c.values[0], c.values[1], c.values[2], c.values[3]);
    if (fading_surfaces_) fading_surfaces_->set_listener(c.values[0], c.values[1], c.values[2], c.values[3]);
    if (ambisonic()) facing_turn_.turn_to(c.values[3]);
}

// A scene swapped or loaded in: its surfaces and umbrella hear the head as it is turned now (a loaded
// scene's surfaces were built for its own listener: on a bus, the facing glides to that one's).
void Renderer::hand_over_listener() {
    if (ambisonic()) {
        facing_turn_.turn_to(surfaces_->facing_rad());
        return;
    }
    if (!head_turned_) return;
    surfaces_->set_head(head_);
    scene_->drops.turn_head(head_, 0);
}

// A texture grain's azimuth: the drop's point on the cap seen from the head (x, y, height above it),
// turned by the head on the panned formats. Ambisonics: the bed's ring is rotated with the bus instead.
double Renderer::grain_azimuth(Point2 at, double height) const {
    if (!head_turned_ || ambisonic()) return std::atan2(at.y, at.x);
    const std::array<double, 9>& h = head_;
    const double x = h[0] * at.x + h[3] * at.y + h[6] * height, y = h[1] * at.x + h[4] * at.y + h[7] * height;
    return std::atan2(y, x);
}

}  // namespace ameoto
