// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The body's facing as a rotation of an encoded AmbiX bus about the vertical: the renderer's world bus
// (the scene's surfaces, encoded in the scene's frame by scene_surfaces.hpp) is turned by it, then the
// whole bus by the head's orientation (AmbixRotation), so that /listener's facing and
// /listener/orientation rotate the sound field without re-encoding anything (docs/output-formats.md,
// "Turning the head").
//
// Interface (audio thread, or before audio starts; plain data, never allocates):
//   FacingTurn t;  t.reset(order, facing_rad);   // at once (construction, a stream's start)
//   t.turn_to(facing_rad);                        // glide there over FacingTurn::glide_frames samples
//                                                 // (nothing when it is there already)
//   t.active()                                    // false at facing 0 and at rest: the caller skips it
//   t.step();                                     // once per sample, before add_turned
//   t.add_turned(in, out);                        // out[acn] += (Z in)[acn]
//
// A body turned counter-clockwise by f hears a source at azimuth a at a - f. In AmbiX (ambisonics.hpp)
// the channel of degree m > 0 of order n carries N P(sin el) cos(m a) and its partner of degree -m
// carries N P(sin el) sin(m a), so with C = cos(m f), S = sin(m f):
//   cos(m (a - f)) = C cos(m a) + S sin(m a),   sin(m (a - f)) = C sin(m a) - S cos(m a)
// (Zotter & Frank, "Ambisonics", Springer 2019, section 5.2.2: a rotation about z mixes only each
// (m, -m) pair). Degree 0 (W, Z, ...) is unchanged. The cost is two multiplications and one addition per
// channel, against the 16 x 16 head rotation's block products.
// The glide crossfades the old and the new matrices (as Renderer::rotate does for the head): each
// pair's (C, S) is blended linearly over glide_frames; a new turn mid-glide starts from the blend it
// had reached, so a stream of updates never jumps.

namespace ameoto {

class FacingTurn {
public:
    static constexpr int glide_frames = 256;   // as Renderer::rotation_ramp_frames: 5.3 ms at 48 kHz

    void reset(int order, double facing_rad);
    void turn_to(double facing_rad);
    bool active() const { return active_; }
    void step();
    void add_turned(const float* in, float* out) const;

private:
    static constexpr int degrees = 4;   // m = 0..3 (index 0 unused)
    int order_ = 1;
    double c_from_[degrees] = {1, 1, 1, 1}, s_from_[degrees] = {};
    double c_to_[degrees] = {1, 1, 1, 1}, s_to_[degrees] = {};
    double c_[degrees] = {1, 1, 1, 1}, s_[degrees] = {};   // this sample's blend
    double facing_ = 0.0;   // the target, rad
    int left_ = 0;
    bool active_ = false;
};

}  // namespace ameoto
