// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The scene's surfaces other than the umbrella, each under its own rain and heard from where it lies:
// drops arrive on each surface as a Poisson process at its area's impact flux for the scene's drop size
// distribution (rain_spawner.hpp), strike it at a uniform point (u, v) with the speed the wind gives
// them along its normal (wind.hpp), and its sound (Pa at 1 m, surface_source.hpp) reaches the listener
// through open air (propagation.hpp: 1/r, the delay r/c, ISO 9613-1 air absorption, gliding when the
// listener moves) and, over 2 channels or more, panned by the azimuth its direction has for the
// listener's head: relative to the facing, then turned by the head's orientation (set_head; the full
// rotation, then the azimuth: panning.hpp), or, on an Ambisonic bus (ambisonic = true: 4, 9 or 16
// channels), encoded by its direction from the listener in the scene's frame, elevation included
// (ambisonics.hpp): the renderer turns that world bus by the facing and the head (listener_rotation.hpp),
// so a turn re-encodes nothing here. A change of direction (a move, a facing, a head turn) glides the
// gains over pan_glide_frames (no click).
//
// Interface:
//   SceneSurfaces s(scene_description, sample_rate, channels, seed);   // off the audio thread; throws
//                                                                      // std::invalid_argument (a surface's reason)
//   SceneSurfaces s(scene_description, sample_rate, channels, seed, full_scale_pa, node);
//                                           // node K (1..16): only the surfaces the scene gives node K;
//                                           // 0 (the default): all of them
//   SceneSurfaces s(..., node, true);       // an Ambisonic bus (ACN/SN3D) of `channels` (4, 9, 16)
//   ---- audio thread: no allocation ----
//   s.set_rate(mm_per_h);                   // every surface's rain ramps there (1 s)
//   s.render(frame, wind);                  // adds this sample of every surface into frame[channel], in
//                                           // full-scale units (1.0 = full_scale_pa)
//   s.set_listener(x, y, z, facing_rad);    // the paths glide there (20 ms); the panning follows
//   s.set_head(h);                          // the head's rotation (head_rotation, row-major): the
//                                           // panned formats' gains glide to it; ignored on a bus
//   s.drops()                               // drops struck so far
//   s.count(), s.distance_m(i), s.delay_samples(i)
//
// Each surface draws its rain (arrivals, sizes, points, the strike's own draws) from a random stream of
// its own, seeded from the seed and its place among the scene's surfaces: a surface sounds the same
// whichever other surfaces are rendered beside it, so a scene split over several nodes (each with the
// same seed) sums to the whole scene's samples (up to the float rounding of the sum's order). The
// scene's first surface's stream is the one all surfaces once shared, so a scene with one surface
// besides an umbrella renders as it did.
//
// r is the distance from the listener's ears to the surface's centre, at least 0.5 m (a surface is no
// point source nearer than its own size allows; the floor keeps a surface under the listener's feet
// finite).

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/ambisonics.hpp"
#include "engine/models/panning.hpp"
#include "engine/render/surface_source.hpp"
#include "engine/scene/propagation.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "engine/scene/wind.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto {

class SceneSurfaces {
public:
    SceneSurfaces(const SceneDescription& scene, double sample_rate, int channels, std::uint64_t seed,
                  double full_scale_pa = 100.0, int node = 0, bool ambisonic = false);

    void set_rate(double mm_per_h);
    void set_rate_now(double mm_per_h);
    void render(float* frame, const Wind& wind);
    void set_listener(double x_m, double y_m, double z_m, double facing_rad);
    void set_head(const std::array<double, 9>& head);
    static constexpr int pan_glide_frames = 256;   // as the bus's rotation (Renderer::rotation_ramp_frames)

    int count() const { return static_cast<int>(placed_.size()); }
    double distance_m(int i) const { return placed_[static_cast<std::size_t>(i)].distance_m; }
    double delay_samples(int i) const { return placed_[static_cast<std::size_t>(i)].path.delay_samples(); }
    std::uint64_t drops() const { return drops_; }
    double facing_rad() const { return facing_rad_; }

private:
    struct Placed {
        std::unique_ptr<SurfaceSource> source;
        RainSpawner rain;
        Random rng;                      // this surface's rain and strikes only
        Propagation path;
        Vec3 centre;
        double distance_m = 1.0;
        std::array<float, max_pan_channels> pan{};   // pan gains, or SH gains (ACN) on an Ambisonic bus
        std::array<float, max_pan_channels> pan_to{}, pan_step{};   // the glide to a new direction
    };
    void place(Placed& p, bool now);
    void glide_all();
    std::vector<Placed> placed_;
    Vec3 listener_{};
    double facing_rad_ = 0.0;
    std::array<double, 9> head_{1, 0, 0, 0, 1, 0, 0, 0, 1};
    bool head_identity_ = true;
    int glide_left_ = 0;
    int channels_ = 1;
    bool ambisonic_ = false;
    double dt_ = 0.0;
    double inverse_full_scale_ = 0.01;
    double density_ = 998.0;
    std::uint64_t drops_ = 0;
};

}  // namespace ameoto
