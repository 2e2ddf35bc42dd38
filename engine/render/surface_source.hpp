// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The surfaces of a scene other than the umbrella (water, plates, ground), behind one small interface, so
// the scene runtime strikes and hears them alike.
//
// Interface:
//   std::unique_ptr<SurfaceSource> s = make_surface_source(description, sample_rate, seed);
//                                            // off the audio thread; throws std::invalid_argument with the
//                                            // surface's name and the reason (unknown material, size...)
//   ---- audio thread: no allocation ----
//   s->strike(D_m, V_m_per_s, density, u, v, rng);   // a drop at (u, v) in 0..1 of the surface's extent
//   double p = s->sample();                          // Pa referred to 1 m from the surface (the scene applies
//                                                    // distance, delay, air absorption and panning)
//   s->area_m2()                                     // horizontal area: the rain it catches
//
// What each kind is: water (pond, puddle): models/water_surface.hpp (Minnaert bubbles and the impact through
// the surface); plate (tin, glass, car-roof): models/modal_plate.hpp, the preset's material at the scene's
// size; ground (leaves, soil): models/soft_ground.hpp.

#include <cstdint>
#include <memory>

#include "engine/core/random.hpp"
#include "engine/scene/scene_description.hpp"

namespace ameoto {

class SurfaceSource {
public:
    virtual ~SurfaceSource() = default;
    virtual void strike(double diameter_m, double speed_m_per_s, double density, double u, double v, Random& rng) = 0;
    virtual double sample() = 0;
    double area_m2() const { return area_m2_; }

protected:
    double area_m2_ = 1.0;
};

std::unique_ptr<SurfaceSource> make_surface_source(const SurfaceDescription& surface, double sample_rate, std::uint64_t seed);

}  // namespace ameoto
