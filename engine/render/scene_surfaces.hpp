#pragma once
// The scene's surfaces other than the umbrella, each under its own rain and heard from where it lies:
// drops arrive on each surface as a Poisson process at its area's impact flux (rain_spawner.hpp), strike it
// at a uniform point (u, v), and its sound (Pa at 1 m, surface_source.hpp) reaches the listener with
// spherical spreading 1/r, the delay r/c (linear-interpolation fractional delay) and, over 2 channels or
// more, panned by its azimuth relative to the listener's facing (panning.hpp).
//
// Interface:
//   SceneSurfaces s(scene_description, sample_rate, channels, seed);   // off the audio thread; throws
//                                                                      // std::invalid_argument (a surface's reason)
//   ---- audio thread: no allocation ----
//   s.set_rate(mm_per_h);                   // every surface's rain ramps there (1 s)
//   s.render(frame, rng);                   // adds this sample of every surface into frame[channel], in
//                                           // full-scale units (1.0 = full_scale_pa)
//   s.drops()                               // drops struck so far
//   s.count(), s.distance_m(i), s.delay_samples(i)
//
// r is the distance from the listener's ears to the surface's centre, at least 0.5 m (a surface is no
// point source nearer than its own size allows; the floor keeps a surface under the listener's feet
// finite). Air absorption over r (ISO 9613-1) is not applied here yet: at the scenes' 1-10 m it takes
// under 1 dB below 8 kHz.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/panning.hpp"
#include "engine/render/surface_source.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto {

class SceneSurfaces {
public:
    SceneSurfaces(const SceneDescription& scene, double sample_rate, int channels, std::uint64_t seed,
                  double full_scale_pa = 100.0);

    void set_rate(double mm_per_h);
    void set_rate_now(double mm_per_h);
    void render(float* frame, Random& rng);

    int count() const { return static_cast<int>(placed_.size()); }
    double distance_m(int i) const { return placed_[static_cast<std::size_t>(i)].distance_m; }
    double delay_samples(int i) const { return placed_[static_cast<std::size_t>(i)].delay; }
    std::uint64_t drops() const { return drops_; }

private:
    struct Placed {
        std::unique_ptr<SurfaceSource> source;
        RainSpawner rain;
        double distance_m = 1.0, delay = 0.0, gain = 1.0;   // gain: 1/r over full scale
        std::array<float, max_pan_channels> pan{};
        std::vector<double> ring;                          // the delay line, a power of two long
        int write = 0, offset = 0;
        double frac = 0.0;
    };
    std::vector<Placed> placed_;
    int channels_ = 1;
    double dt_ = 0.0;
    double density_ = 998.0;
    std::uint64_t drops_ = 0;
};

}  // namespace ameoto
