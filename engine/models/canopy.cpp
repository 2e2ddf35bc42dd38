#include "engine/models/canopy.hpp"

#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"

namespace ameoto {

Canopy::Canopy(const CanopyGeometry& geometry, const MembraneMaterial& material, double time_step_s)
    : geometry_(geometry) {
    if (geometry.panels < 3 || geometry.panels > 64) throw std::invalid_argument("a canopy has 3 to 64 panels");
    if (!(geometry.radius_m > 0.0)) throw std::invalid_argument("canopy radius must be positive");
    const double half_angle = constants::pi / geometry.panels;
    half_width_ = geometry.radius_m * std::sin(half_angle);
    height_ = geometry.radius_m * std::cos(half_angle);
    // Counter-clockwise: the hem (free), then the right rib and the left rib (fixed).
    outline_ = {{{-half_width_, 0.0}, false}, {{half_width_, 0.0}, true}, {{0.0, height_}, true}};
    // Every panel is the same body; build it once and copy it.
    const Membrane prototype = build_membrane(outline_, geometry.masses_per_panel, material, time_step_s);
    panels_.assign(static_cast<std::size_t>(geometry.panels), prototype);
}

double Canopy::panel_azimuth(int panel) const { return 2.0 * constants::pi * panel / geometry_.panels; }

Point2 Canopy::to_local(int panel, double x, double y) const {
    const double a = panel_azimuth(panel);
    const double along = x * std::cos(a) + y * std::sin(a);      // distance out from the shaft
    const double across = -x * std::sin(a) + y * std::cos(a);
    return {across, height_ - along};
}

CanopyHit Canopy::locate(double x, double y) const {
    const double sector = 2.0 * constants::pi / geometry_.panels;
    int panel = static_cast<int>(std::lround(std::atan2(y, x) / sector));
    panel = ((panel % geometry_.panels) + geometry_.panels) % geometry_.panels;
    const Point2 local = to_local(panel, x, y);
    if (!polygon_contains(outline_, local)) return {};
    return {panel, panels_[static_cast<std::size_t>(panel)].lattice.nearest_node(local)};
}

Point2 Canopy::sample_point(Random& rng) const {
    // Panels have equal areas: pick one, then a uniform point in its triangle (square-root method).
    const int panel = static_cast<int>(rng.uniform() * geometry_.panels) % geometry_.panels;
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    // Triangle shaft (origin), rib tips at azimuth +- half sector, radius R.
    const double a = panel_azimuth(panel), half = constants::pi / geometry_.panels;
    const double r = geometry_.radius_m;
    const Point2 b{r * std::cos(a - half), r * std::sin(a - half)};
    const Point2 c{r * std::cos(a + half), r * std::sin(a + half)};
    return {r1 * ((1.0 - r2) * b.x + r2 * c.x), r1 * ((1.0 - r2) * b.y + r2 * c.y)};
}

void Canopy::apply_force(CanopyHit hit, double newtons) {
    if (hit.panel < 0) return;
    panels_[static_cast<std::size_t>(hit.panel)].network.apply_force(hit.node, newtons);
}

void Canopy::step(double* panel_forces) {
    for (std::size_t k = 0; k < panels_.size(); ++k) panel_forces[k] = panels_[k].network.step();
}

int Canopy::reset_unstable() {
    int resets = 0;
    for (auto& p : panels_) resets += p.network.guard() ? 1 : 0;   // non-finite or runaway energy
    return resets;
}

Point2 Canopy::panel_centroid(int panel) const {
    const double a = panel_azimuth(panel);
    const double d = 2.0 * height_ / 3.0;   // centroid of the triangle, from the shaft
    return {d * std::cos(a), d * std::sin(a)};
}

double Canopy::area() const { return geometry_.panels * half_width_ * height_; }

}  // namespace ameoto
