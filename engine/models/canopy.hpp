#pragma once
// An umbrella canopy: N identical panels, each a membrane fixed on its two ribs and free at its hem.
//
// Interface:
//   Canopy canopy(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), time_step_s);   // allocates
//   canopy.locate(x, y)            // -> {panel, node} under a point in canopy coordinates, or panel -1
//   canopy.sample_point(rng)       // a point uniform over the canopy's area (for rain)
//   canopy.apply_force(hit, N)     // a vertical force on one mass for the next step
//   canopy.step(panel_forces)      // one sample: fills one net force per panel (N); no allocation
//   canopy.reset_unstable()        // runtime guard: resets any panel whose state went non-finite or
//                                  // whose energy ran away (core/stability.hpp); returns how many
//
// Geometry (seed section 5.1.2, Fig. 10-11): seen from above, panel k is the triangle between the
// umbrella's centre and two neighbouring rib tips at radius R, centred on azimuth 2 pi k / N. Canopy
// coordinates: x, y in m from the shaft, horizontal. Curvature is ignored here (a flat projection);
// the canopy's plan area is N R^2 sin(2 pi / N) / 2 (0.707 m^2 for 8 panels of 0.5 m).

#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/membrane.hpp"

namespace ameoto {

struct CanopyGeometry {
    int panels = 8;
    double radius_m = 0.5;
    int masses_per_panel = 50;
};

struct CanopyHit {
    int panel = -1;   // -1: the point is not on the canopy
    int node = -1;
};

class Canopy {
public:
    Canopy(const CanopyGeometry& geometry, const MembraneMaterial& material, double time_step_s);

    CanopyHit locate(double x, double y) const;
    Point2 sample_point(Random& rng) const;
    void apply_force(CanopyHit hit, double newtons);
    void step(double* panel_forces);
    int reset_unstable();

    int panel_count() const { return static_cast<int>(panels_.size()); }
    double panel_azimuth(int panel) const;      // rad, direction of the panel's centre line
    Point2 panel_centroid(int panel) const;     // m, canopy coordinates
    double area() const;                        // m^2, plan area of all panels
    const CanopyGeometry& geometry() const { return geometry_; }
    const Membrane& panel(int k) const { return panels_[static_cast<std::size_t>(k)]; }

private:
    // Local panel frame: hem along y = 0 from (-w, 0) to (w, 0), apex (the shaft) at (0, h).
    Point2 to_local(int panel, double x, double y) const;
    CanopyGeometry geometry_;
    double half_width_ = 0.0, height_ = 0.0;
    std::vector<PolygonEdge> outline_;
    std::vector<Membrane> panels_;
};

}  // namespace ameoto
