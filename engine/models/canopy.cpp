// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/canopy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "engine/core/physical_constants.hpp"

namespace ameoto {
namespace {

// "" when the geometry is valid, else why not.
std::string geometry_problem(const CanopyGeometry& g) {
    if (g.panels < 3 || g.panels > 64) return "a canopy has 3 to 64 panels";
    if (!(g.radius_m > 0.0) || !std::isfinite(g.radius_m)) return "canopy radius must be positive";
    if (g.masses_per_panel < 1) return "a panel needs at least one mass";
    if (!(g.curvature_radius_m > g.radius_m))
        return "the radius of curvature must exceed the canopy's radius (infinity: flat)";
    return {};
}

// Counter-clockwise: the hem (free), then the right rib and the left rib (fixed).
std::vector<PolygonEdge> panel_outline(const CanopyGeometry& g) {
    const double half_angle = constants::pi / g.panels;
    const double w = g.radius_m * std::sin(half_angle), h = g.radius_m * std::cos(half_angle);
    return {{{-w, 0.0}, false}, {{w, 0.0}, true}, {{0.0, h}, true}};
}

}  // namespace

MaterialCheck Canopy::check(const CanopyGeometry& geometry, const MembraneMaterial& material, double time_step_s,
                            const NetworkOptions& options) {
    const std::string problem = geometry_problem(geometry);
    if (!problem.empty()) return MaterialCheck{false, problem, {}};
    // Every panel is the same body: one verdict for all.
    return check_membrane_material(panel_outline(geometry), geometry.masses_per_panel, material, time_step_s, options);
}

Canopy::Canopy(const CanopyGeometry& geometry, const MembraneMaterial& material, double time_step_s,
               const NetworkOptions& options)
    : geometry_(geometry) {
    const std::string problem = geometry_problem(geometry);
    if (!problem.empty()) throw std::invalid_argument(problem);
    const MaterialCheck valid = validate_membrane_material(material);
    if (!valid.ok) throw std::invalid_argument(valid.reason);
    const double half_angle = constants::pi / geometry.panels;
    half_width_ = geometry.radius_m * std::sin(half_angle);
    height_ = geometry.radius_m * std::cos(half_angle);
    outline_ = panel_outline(geometry);
    // Every panel is the same body; build it once and copy it (throws StabilityError when refused).
    const Membrane prototype = build_membrane(outline_, geometry.masses_per_panel, material, time_step_s, options);
    panels_.assign(static_cast<std::size_t>(geometry.panels), prototype);
    nodes_ = prototype.network.mass_count();
    displacements_.assign(static_cast<std::size_t>(nodes_), 0.0);
    laned_ = LanedNetwork::supports(prototype.network.integrator());
    lanes_ = (geometry.panels + 3) / 4 * 4;
    if (laned_) lanes_state_.init(prototype.network, geometry.panels);
    lane_low_.assign(static_cast<std::size_t>(lanes_), 0.0);
    lane_high_.assign(static_cast<std::size_t>(lanes_), 0.0);
    const double sector = 2.0 * constants::pi / geometry.panels;
    for (int k = 0; k < geometry.panels; ++k) {
        cos_azimuth_.push_back(std::cos(panel_azimuth(k)));
        sin_azimuth_.push_back(std::sin(panel_azimuth(k)));
    }
    for (int k = 0; k <= geometry.panels; ++k)
        boundary_.push_back({std::cos((k - 0.5) * sector), std::sin((k - 0.5) * sector)});
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        const Point2 a = outline_[e].start, b = outline_[(e + 1) % outline_.size()].start;
        edges_[e] = {a.x, a.y, b.x - a.x, b.y - a.y, std::hypot(b.x - a.x, b.y - a.y)};
    }
    rest_.resize(static_cast<std::size_t>(geometry.panels * nodes_));
    normal_.resize(rest_.size());
    for (int k = 0; k < geometry.panels; ++k) {
        for (int i = 0; i < nodes_; ++i) {
            const Point2 p = to_canopy(k, prototype.lattice.nodes[static_cast<std::size_t>(i)]);
            rest_[index(k, i)] = {p.x, p.y, rest_height(p.x, p.y)};
            normal_[index(k, i)] = surface_normal(p.x, p.y);
        }
    }
}

double Canopy::panel_azimuth(int panel) const { return 2.0 * constants::pi * panel / geometry_.panels; }

Point2 Canopy::to_local(int panel, double x, double y) const {
    // The rotation by -azimuth, with the constructor's std::cos / std::sin of it: the same values the
    // same expressions gave when they were evaluated here.
    const double c = cos_azimuth_[static_cast<std::size_t>(panel)], s = sin_azimuth_[static_cast<std::size_t>(panel)];
    const double along = x * c + y * s;      // distance out from the shaft
    const double across = -x * s + y * c;
    return {across, height_ - along};
}

Point2 Canopy::to_canopy(int panel, Point2 local) const {
    const double a = panel_azimuth(panel);
    const double along = height_ - local.y, across = local.x;
    return {along * std::cos(a) - across * std::sin(a), along * std::sin(a) + across * std::cos(a)};
}

double Canopy::rest_height(double x, double y) const {
    if (flat()) return 0.0;
    const double rc = geometry_.curvature_radius_m, r2 = x * x + y * y;
    return -r2 / (std::sqrt(rc * rc - r2) + rc);   // sqrt(Rc^2 - r^2) - Rc without cancellation
}

Vec3 Canopy::surface_normal(double x, double y) const {
    if (flat()) return {0.0, 0.0, 1.0};
    const double rc = geometry_.curvature_radius_m;
    const double nx = x / rc, ny = y / rc;
    return {nx, ny, std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny))};
}

Vec3 Canopy::node_position(int panel, int node) const {
    return rest_position(panel, node) + displacement(panel, node) * normal(panel, node);
}

void Canopy::set_air(std::shared_ptr<const AirCanopyModes> modes) {
    if (modes && modes->nodes != panel_count() * nodes_)
        throw std::invalid_argument("Canopy::set_air: the modes are another canopy's");
    air_ = std::move(modes);
    if (air_) air_state_.init(*air_);
}

double Canopy::displacement(int panel, int node) const {
    if (air_) return air_state_.displacement(*air_, static_cast<int>(index(panel, node)));
    if (laned_) return lanes_state_.position(panel, node);
    return panels_[static_cast<std::size_t>(panel)].network.position(node);
}

double Canopy::normal_velocity(int panel, int node) const {
    if (air_) return air_state_.velocity(*air_, static_cast<int>(index(panel, node)));
    if (laned_) return lanes_state_.velocity(panel, node);
    return panels_[static_cast<std::size_t>(panel)].network.velocity(node);
}

void Canopy::panel_positions(int panel, double* out) const {
    if (air_) {
        for (int i = 0; i < nodes_; ++i) out[i] = displacement(panel, i);
        return;
    }
    if (laned_) return lanes_state_.positions(panel, out);
    panels_[static_cast<std::size_t>(panel)].network.positions(out);
}

void Canopy::panel_velocities(int panel, double* out) const {
    if (air_) {
        for (int i = 0; i < nodes_; ++i) out[i] = normal_velocity(panel, i);
        return;
    }
    if (laned_) return lanes_state_.velocities(panel, out);
    panels_[static_cast<std::size_t>(panel)].network.velocities(out);
}

bool Canopy::panel_finite(int panel) const {
    if (air_) return air_state_.finite();
    return laned_ ? lanes_state_.finite(panel) : panels_[static_cast<std::size_t>(panel)].network.finite();
}

// In air the modes are the whole canopy's: each panel is given an equal share of their energy.
double Canopy::panel_energy(int panel) const {
    if (air_) return air_state_.energy() / panel_count();
    return laned_ ? lanes_state_.energy(panel)
                  : panels_[static_cast<std::size_t>(panel)].network.kinetic_plus_potential_energy();
}

std::uint64_t Canopy::panel_guard_resets(int panel) const {
    if (air_) return air_resets_;
    return laned_ ? lanes_state_.guard_resets(panel) : panels_[static_cast<std::size_t>(panel)].network.guard_resets();
}

// Node-major, out[node * lanes_ + panel]: the lanes' own layout, one pass over the whole canopy.
void Canopy::velocities(double* out) const {
    if (laned_ && !air_) return lanes_state_.velocities(out);
    const auto stride = static_cast<std::size_t>(lanes_);
    std::fill(out, out + stride * static_cast<std::size_t>(nodes_), 0.0);
    if (air_) {
        for (int k = 0; k < panel_count(); ++k)
            for (int i = 0; i < nodes_; ++i)
                out[static_cast<std::size_t>(i) * stride + static_cast<std::size_t>(k)] = normal_velocity(k, i);
        return;
    }
    double* const v = displacements_.data();
    for (std::size_t k = 0; k < panels_.size(); ++k) {
        panels_[k].network.velocities(v);
        for (std::size_t i = 0; i < static_cast<std::size_t>(nodes_); ++i) out[i * stride + k] = v[i];
    }
}

// The extremes of u over every node, as displacement() reads them. A NaN (a panel gone unstable,
// before the runtime guard resets it) never wins a comparison, so it is passed over; with no finite
// node at all the range is empty (lowest +infinity, highest -infinity).
DisplacementRange Canopy::displacement_range() const {
    if (air_) {
        const double b = air_state_.displacement_bound(*air_);
        if (!std::isfinite(b))
            return {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        return {-b, b};
    }
    if (laned_) return laned_displacement_range();
    DisplacementRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    double* const u_all = displacements_.data();
    for (const Membrane& p : panels_) {
        p.network.positions(u_all);   // position(i) for every node, one call
        for (int i = 0; i < nodes_; ++i) {
            const double u = u_all[i];
            r.lowest = std::min(r.lowest, u);
            r.highest = std::max(r.highest, u);
        }
    }
    return r;
}

namespace {

// Per lane, the extremes over the nodes in node order (std::min / std::max: a value replaces the
// running one only when strictly beyond it, so NaN never wins). lanes is a multiple of 4 (Canopy pads
// to it). With SSE2 (every x86-64), four lanes at a time in registers: minpd(x, y) gives y unless
// x < y, so minpd(value, low) is std::min(low, value) exactly (equal values, +0 and -0, and NaN keep
// low), and maxpd(value, high) is std::max(high, value): the same doubles as the scalar loop, which
// kept its running extremes in memory and cost about 10 instructions a node (4 300 a reading of the
// default canopy, read every step while a splash hovers over it: drop_on_canopy_collide.cpp, collide()).
void lane_extremes(std::size_t nodes, std::size_t lanes, const double* __restrict u, double* __restrict low,
                   double* __restrict high) {
#if defined(__SSE2__)
    for (std::size_t j = 0; j + 4 <= lanes; j += 4) {
        __m128d low01 = _mm_set1_pd(std::numeric_limits<double>::infinity()), low23 = low01;
        __m128d high01 = _mm_set1_pd(-std::numeric_limits<double>::infinity()), high23 = high01;
        for (std::size_t i = 0; i < nodes; ++i) {
            const double* const at = u + i * lanes + j;
            const __m128d v01 = _mm_loadu_pd(at), v23 = _mm_loadu_pd(at + 2);
            low01 = _mm_min_pd(v01, low01);
            low23 = _mm_min_pd(v23, low23);
            high01 = _mm_max_pd(v01, high01);
            high23 = _mm_max_pd(v23, high23);
        }
        _mm_storeu_pd(low + j, low01);
        _mm_storeu_pd(low + j + 2, low23);
        _mm_storeu_pd(high + j, high01);
        _mm_storeu_pd(high + j + 2, high23);
    }
#else
    for (std::size_t j = 0; j < lanes; ++j) {
        low[j] = std::numeric_limits<double>::infinity();
        high[j] = -std::numeric_limits<double>::infinity();
    }
    for (std::size_t i = 0; i < nodes; ++i) {
        const double* const row = u + i * lanes;
        for (std::size_t j = 0; j < lanes; ++j) {
            low[j] = std::min(low[j], row[j]);
            high[j] = std::max(high[j], row[j]);
        }
    }
#endif
}

}  // namespace

// The same extremes as the panel-by-panel scan, from the lanes in one pass: each lane keeps its own
// first extreme in node order, and the panels are then taken in order, so among equal values (+0 and
// -0) the same one wins as in the panel-major scan. Padding lanes are not read.
DisplacementRange Canopy::laned_displacement_range() const {
    lane_extremes(static_cast<std::size_t>(nodes_), static_cast<std::size_t>(lanes_), lanes_state_.positions(),
                  lane_low_.data(), lane_high_.data());
    DisplacementRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (std::size_t k = 0; k < panels_.size(); ++k) {
        r.lowest = std::min(r.lowest, lane_low_[k]);
        r.highest = std::max(r.highest, lane_high_[k]);
    }
    return r;
}

// Panel k covers the azimuths within half a sector of its centre line, 2 pi k / N: by definition the
// panel is round(atan2(y, x) / sector) mod N (panel_by_atan2). To skip the atan2, an approximate
// azimuth (within 1e-5 rad) proposes a panel, and two cross products confirm that (x, y) lies strictly
// inside that panel's sector, between its boundary rays b_k and b_k+1: b_k x p > 0 > b_k+1 x p (a wedge
// narrower than pi, as N >= 3). The margin, 1e-10 (|x| + |y|) >= 1e-10 |p|, puts p more than 1e-10 rad
// inside the sector: far beyond the rounding of these products (a few 1e-16 (|x| + |y|)) and of
// atan2(y, x) / sector (a few 1e-16 relative), so atan2 would round to the same panel. Only points
// within that margin of a rib's line (or of the shaft, where both products vanish), or where the
// approximation missed by a panel, ask atan2; so do NaN and infinities (the comparisons fail).
int Canopy::panel_at(double x, double y) const {
    const int n = geometry_.panels;
    const double ax = std::fabs(x), ay = std::fabs(y);
    const double hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    if (ax + ay > 0.0 && ax + ay <= std::numeric_limits<double>::max()) {   // not the shaft, NaN or infinite
        // atan(z) on [0, 1] to 1e-5 rad (Abramowitz & Stegun 4.4.47), then the octant.
        const double z = lo / hi, z2 = z * z;
        double a = z * (0.9998660 + z2 * (-0.3302995 + z2 * (0.1801410 + z2 * (-0.0851330 + z2 * 0.0208351))));
        if (ay > ax) a = 0.5 * constants::pi - a;
        if (x < 0.0) a = constants::pi - a;
        if (y < 0.0) a = -a;
        // a / sector is in [-N/2, N/2]: shifted positive, the truncation rounds to the nearest panel.
        int k = static_cast<int>(a * (n / (2.0 * constants::pi)) + 0.5 + n) - n;
        if (k < 0) k += n;
        if (k >= n) k -= n;
        const Point2 b0 = boundary_[static_cast<std::size_t>(k)], b1 = boundary_[static_cast<std::size_t>(k) + 1];
        const double margin = 1e-10 * (ax + ay);
        if (b0.x * y - b0.y * x > margin && b1.x * y - b1.y * x < -margin) return k;
    }
    return panel_by_atan2(x, y);
}

int Canopy::panel_by_atan2(double x, double y) const {
    const double sector = 2.0 * constants::pi / geometry_.panels;
    const int panel = static_cast<int>(std::lround(std::atan2(y, x) / sector));
    return ((panel % geometry_.panels) + geometry_.panels) % geometry_.panels;
}

// polygon_contains(outline_, local) (core/triangular_lattice.cpp): outside when any edge's signed
// distance (e x (p - a)) / |e| is negative. Dividing by the positive length keeps the sign unless the
// quotient underflows to -0, so the division (to compare exactly as polygon_contains does) is only
// evaluated where the cross product is already negative.
bool Canopy::inside_outline(Point2 p) const {
    for (const OutlineEdge& e : edges_) {
        const double cross = e.ex * (p.y - e.ay) - e.ey * (p.x - e.ax);
        if (cross < 0.0 && cross / e.length < 0.0) return false;
    }
    return true;
}

// Every panel's lattice is the prototype's (the constructor copies it): the first panel's serves all,
// so one node index stays in cache.
CanopyHit Canopy::locate(double x, double y) const {
    const int panel = panel_at(x, y);
    const Point2 local = to_local(panel, x, y);
    if (!inside_outline(local)) return {};
    return {panel, panels_.front().lattice.nearest_node(local)};
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
    if (air_) return air_state_.apply_force(*air_, static_cast<int>(index(hit.panel, hit.node)), newtons);
    if (laned_) return lanes_state_.apply_force(hit.panel, hit.node, newtons);
    panels_[static_cast<std::size_t>(hit.panel)].network.apply_force(hit.node, newtons);
}

void Canopy::step(double* panel_forces) {
    if (air_) {
        air_state_.step(*air_);
        std::fill(panel_forces, panel_forces + panels_.size(), 0.0);
        return;
    }
    if (laned_) return lanes_state_.step(panel_forces);
    for (std::size_t k = 0; k < panels_.size(); ++k) panel_forces[k] = panels_[k].network.step();
}

int Canopy::reset_unstable() {
    if (air_) {   // exact and unconditionally stable: only a non-finite input can spoil it
        if (air_state_.finite()) return 0;
        air_state_.reset();
        ++air_resets_;
        return panel_count();
    }
    int resets = 0;
    for (int k = 0; k < panel_count(); ++k) {   // non-finite or runaway energy
        const bool reset = laned_ ? lanes_state_.guard(k) : panels_[static_cast<std::size_t>(k)].network.guard();
        resets += reset ? 1 : 0;
    }
    return resets;
}

Point2 Canopy::panel_centroid(int panel) const {
    const double a = panel_azimuth(panel);
    const double d = 2.0 * height_ / 3.0;   // centroid of the triangle, from the shaft
    return {d * std::cos(a), d * std::sin(a)};
}

double Canopy::area() const { return geometry_.panels * half_width_ * height_; }

}  // namespace ameoto
