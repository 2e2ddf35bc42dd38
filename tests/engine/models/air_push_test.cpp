// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/air_push: the crossover above the canopy's modes, each node's filter for the
// compressible push, and DipoleRadiation playing them (dipole_radiation.hpp, DipoleOptions).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_canopy.hpp"
#include "engine/models/air_push.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/dipole_radiation.hpp"
#include "engine/reference/screen_far_field.hpp"
#include "tests/support/relative_approx.hpp"
#include "tests/support/rt_probe_scope.hpp"

namespace ameoto {

namespace {

using cplx = std::complex<double>;
constexpr double rate = 48000.0;

// The default canopy in air at 48 kHz, built once for the file (about 0.5 s).
const Canopy& air_canopy() {
    static const std::unique_ptr<Canopy> canopy = [] {
        auto c = std::make_unique<Canopy>(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / rate);
        c->set_air(build_air_canopy_modes(*c, 1.0 / rate));
        return c;
    }();
    return *canopy;
}

cplx section_response(const Biquad& s, cplx z) {
    return (s.b0 + s.b1 / z + s.b2 / (z * z)) / (1.0 + s.a1 / z + s.a2 / (z * z));
}
cplx half_response(const Biquad (&half)[4], double hz) {
    const cplx z = std::polar(1.0, 2.0 * constants::pi * hz / rate);
    cplx h = 1.0;
    for (const Biquad& s : half) h *= section_response(s, z);
    return h;
}

// A filter's transfer at hz, from the step's force to the samples it adds: sum_j fir[j] z^-(offset + j).
cplx filter_response(const PushFilters& f, std::size_t node, double hz) {
    cplx h = 0.0;
    for (int j = 0; j < f.taps; ++j)
        h += f.fir[node * static_cast<std::size_t>(f.taps) + static_cast<std::size_t>(j)] *
             std::polar(1.0, -2.0 * constants::pi * hz / rate * (f.offset[node] + j));
    return h;
}

struct PointView {
    PushPoint point;
    PushScreen screen;
};

// The point as the dipoles see it (r, cos(theta) per node; D the nearest node's delay), every node of
// areal density s, each node's push from its tile (the disc of its area) or, tiles false, a point.
PointView view(const Canopy& canopy, Vec3 listener, double s, bool tiles = true) {
    const AirCanopyModes& m = *canopy.air_modes();
    PointView v;
    double nearest = 1e300;
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            const Vec3 d = listener - canopy.rest_position(k, i);
            v.point.r.push_back(norm(d));
            v.point.cos_theta.push_back(dot(d, canopy.normal(k, i)) / norm(d));
            v.screen.areal_density.push_back(canopy.panel(k).network.mass(i) > 0.0 ? s : 0.0);
            const double area = m.node_area[static_cast<std::size_t>(k * canopy.nodes_per_panel() + i)];
            v.screen.tile_radius.push_back(tiles ? std::sqrt(area / constants::pi) : 0.0);
            nearest = std::min(nearest, norm(d));
        }
    v.point.delay = static_cast<int>(std::floor(nearest / (constants::speed_of_sound_air / rate)));
    return v;
}

}  // namespace

TEST_CASE("air push: the crossover's halves are in phase and sum to an all-pass, above the highest mode") {
    // Linkwitz-Riley of order 8 (Linkwitz, JAES 24, 1976): LP + HP = B(-s) / B(s), |LP + HP| = 1, and
    // LP, HP in phase at every frequency (HP / LP = (s / wc)^8, real and positive on the axis).
    const AirCanopyModes& m = *air_canopy().air_modes();
    const PushCrossover x = push_crossover(m);
    const double top = m.omega.maxCoeff() / (2.0 * constants::pi);
    CHECK(x.hz == test::relative(1.2 * top).epsilon(1e-12));
    double worst_sum = 0.0, worst_phase = 0.0;
    for (double hz = 10.0; hz < 0.5 * rate; hz *= 1.05) {
        const cplx lp = half_response(x.low, hz), hp = half_response(x.high, hz);
        worst_sum = std::max(worst_sum, std::abs(std::abs(lp + hp) - 1.0));
        worst_phase = std::max(worst_phase, std::abs(std::abs(lp + hp) - std::abs(lp) - std::abs(hp)));
    }
    CHECK(worst_sum < 1e-9);
    CHECK(worst_phase < 1e-9);
    // The highest mode loses 20 log10(1 + (1 / 1.2)^8) = 1.82 dB to the low half.
    CHECK(20.0 * std::log10(std::abs(half_response(x.low, top))) == doctest::Approx(-1.82).epsilon(0.01));
    CHECK(20.0 * std::log10(std::abs(half_response(x.low, 2.0 * x.hz))) < -45.0);
    CHECK(20.0 * std::log10(std::abs(half_response(x.high, 0.5 * x.hz))) < -45.0);
    // No room above the modes at a low rate: no crossover (the modes alone).
    // (At 3 kHz the corner, 1.2 x the highest mode, is over 0.3 of the rate.)
    Canopy slow(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / 3000.0);
    slow.set_air(build_air_canopy_modes(slow, 1.0 / 3000.0));
    CHECK(push_crossover(*slow.air_modes()).hz == 0.0);
}

TEST_CASE("air push: a tile's directivity is a uniform disc's, 2 J1(x) / x") {
    // Values of J1 from Abramowitz & Stegun, table 9.1: J1(1) = 0.4400506, J1(2) = 0.5767248; the first
    // zero of J1 at 3.8317060.
    CHECK(tile_directivity(0.0) == 1.0);
    CHECK(tile_directivity(1e-6) == test::relative(1.0).epsilon(1e-12));
    CHECK(tile_directivity(1.0) == test::relative(2.0 * 0.4400506).epsilon(1e-6));
    CHECK(tile_directivity(2.0) == test::relative(0.5767248).epsilon(1e-6));
    CHECK(std::abs(tile_directivity(3.8317060)) < 1e-6);
    // Against the standard library's J1 from 0 to 12 (a 3 cm tile at 22 kHz, 90 degrees off: 12.1), both
    // sides of A & S's two approximations' seam at 3: within 1e-7.
    double worst = 0.0;
    for (double x = 1e-3; x <= 12.0; x += 1e-3) worst = std::max(worst, std::abs(tile_directivity(x) - 2.0 * std::cyl_bessel_j(1.0, x) / x));
    CHECK(worst < 1e-7);
    CHECK(tile_directivity(-2.0) == tile_directivity(2.0));
}

TEST_CASE("air push: a node's filter is the high half of its tile's force on a limp screen in compressible air") {
    const Canopy& canopy = air_canopy();
    const AirCanopyModes& m = *canopy.air_modes();
    const PushCrossover x = push_crossover(m);
    const double s = canopy.panel(0).material.areal_density, c = constants::speed_of_sound_air, rho = constants::air_density;
    const Point2 centroid = canopy.panel_centroid(0);
    const int node = canopy.locate(centroid.x, centroid.y).node;   // panel 0
    const Vec3 listener{1.0, 0.0, -0.3};
    const PointView v = view(canopy, listener, s);
    const PushFilters f = design_push_filters(m, x, v.screen, v.point, AirMedium{});
    REQUIRE(f.taps > 0);
    const auto e = static_cast<std::size_t>(node);
    const double r = v.point.r[e], cos_theta = v.point.cos_theta[e], lag = v.point.delay / rate;
    const double a = v.screen.tile_radius[e], sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
    INFO("r " << r << " m, cos(theta) " << cos_theta << ", D T = " << lag * 1e3 << " ms, tile radius " << a << " m");
    REQUIRE(a > 0.02);   // the centroid's tile: about a 50th of the panel's 0.088 m^2
    REQUIRE(a < 0.03);

    // The high half of the dipole of f / (1 + i beta |cos(theta)|) from the node's tile, at the modes' bulk
    // delay D (air_push.hpp), the force held over the step: within 1 % from the corner up.
    for (double hz : {x.hz, 1.5e3, 2.5e3, 3.0e3, 4.0e3, 6.0e3, 8.0e3, 12.0e3}) {
        const double w = 2.0 * constants::pi * hz;
        const double beta = w * s / (2.0 * rho * c);
        const cplx held = (std::polar(1.0, w / rate) - 1.0) / cplx(0.0, w / rate);
        const cplx expected = half_response(x.high, hz) * cos_theta / (4.0 * constants::pi) * cplx(1.0 / (r * r), w / (c * r)) *
                              std::polar(1.0, -w * lag) / cplx(1.0, beta * std::abs(cos_theta)) * held *
                              (2.0 * std::cyl_bessel_j(1.0, w / c * a * sin_theta) / (w / c * a * sin_theta));
        const cplx got = filter_response(f, e, hz);
        INFO(hz << " Hz: " << got << " against " << expected);
        CHECK(std::abs(got - expected) < 0.01 * std::abs(expected));
    }
    // Where the halves overlap, and above, the push comes at the modes' bulk delay D: the phase's slope
    // less the high half's, the near field's and the jump's is D T, within 2 us.
    for (double hz : {0.9 * x.hz, 1.0 * x.hz, 1.1 * x.hz, 3000.0}) {
        const double dh = 2.0;
        const double slope = -std::arg(filter_response(f, e, hz + dh) / filter_response(f, e, hz - dh)) / (2.0 * constants::pi * 2.0 * dh);
        // The high half's own group delay, taken out: what is left is the filter's delay.
        const double own = -std::arg(half_response(x.high, hz + dh) / half_response(x.high, hz - dh)) / (2.0 * constants::pi * 2.0 * dh);
        // The dipole's near field and the jump's pole turn the phase a little: both computed here.
        auto rest = [&](double h) {
            const double w = 2.0 * constants::pi * h;
            return cplx(1.0 / (r * r), w / (c * r)) / cplx(1.0, w * s / (2.0 * rho * c) * std::abs(cos_theta)) *
                   (std::polar(1.0, w / rate) - 1.0) / cplx(0.0, w / rate);
        };
        const double shape = -std::arg(rest(hz + dh) / rest(hz - dh)) / (2.0 * constants::pi * 2.0 * dh);
        INFO(hz << " Hz: delay error " << (slope - own - shape - lag) * 1e6 << " us");
        CHECK(std::abs(slope - own - shape - lag) < 2e-6);
    }
    // A node that cannot move (on a rib) has no filter.
    for (std::size_t i = 0; i < v.screen.areal_density.size(); ++i)
        if (v.screen.areal_density[i] == 0.0) {
            bool zero = true;
            for (int j = 0; j < f.taps; ++j) zero = zero && f.fir[i * static_cast<std::size_t>(f.taps) + static_cast<std::size_t>(j)] == 0.0;
            CHECK(zero);
            break;
        }
}

TEST_CASE("air push: a heavy screen's push is the mass law's, the same in every direction for a point") {
    // Far above beta = 1 a point force on a limp plate radiates p = rho0 F / (2 pi r s) whatever the
    // direction (the plate's velocity F / (i omega s) at the trace wavenumber, Rayleigh's integral;
    // Junger & Feit, Sound, Structures, and Their Interaction, 1986, on point-excited plates). Checked at
    // 3 kHz, 3 m away, on a 5 kg/m^2 screen (beta = 110): within 5 % (the near field, 1 / kr = 0.018,
    // and 1 / beta), at 25 and 70 degrees from the normal, for a point (tile radius 0); the node's tile
    // takes its disc's directivity off it, the same 5 %.
    const Canopy& canopy = air_canopy();
    const AirCanopyModes& m = *canopy.air_modes();
    const PushCrossover x = push_crossover(m);
    const double s = 5.0, hz = 3000.0;
    const Point2 centroid = canopy.panel_centroid(0);
    const auto e = static_cast<std::size_t>(canopy.locate(centroid.x, centroid.y).node);
    const Vec3 y = canopy.rest_position(0, static_cast<int>(e)), n = canopy.normal(0, static_cast<int>(e));
    for (double degrees : {25.0, 70.0}) {
        const double a = degrees * constants::pi / 180.0;
        // A direction in the plane of the normal and the x axis, below the canopy (the normal points up).
        Vec3 side{1.0, 0.0, 0.0};
        side = side - dot(side, n) * n;
        side = side / norm(side);
        const Vec3 listener = y - (3.0 * std::cos(a)) * n + (3.0 * std::sin(a)) * side;
        const PointView point = view(canopy, listener, s, false), tiled = view(canopy, listener, s);
        const PushFilters f = design_push_filters(m, x, point.screen, point.point, AirMedium{});
        const PushFilters f_tiled = design_push_filters(m, x, tiled.screen, tiled.point, AirMedium{});
        const double r = point.point.r[e];
        const double held = std::abs((std::polar(1.0, 2.0 * constants::pi * hz / rate) - 1.0) / cplx(0.0, 2.0 * constants::pi * hz / rate));
        const double mass_law = constants::air_density / (2.0 * constants::pi * r * s) * std::abs(half_response(x.high, hz)) * held;
        const double k_a_sin = 2.0 * constants::pi * hz / constants::speed_of_sound_air * tiled.screen.tile_radius[e] *
                               std::sqrt(1.0 - tiled.point.cos_theta[e] * tiled.point.cos_theta[e]);
        INFO(degrees << " degrees: |p| " << std::abs(filter_response(f, e, hz)) << " Pa/N against " << mass_law << "; tiled "
                     << std::abs(filter_response(f_tiled, e, hz)) << ", k a sin(theta) " << k_a_sin);
        CHECK(std::abs(filter_response(f, e, hz)) == test::relative(mass_law).epsilon(0.05));
        CHECK(std::abs(filter_response(f_tiled, e, hz)) == test::relative(mass_law * tile_directivity(k_a_sin)).epsilon(0.05));
        if (degrees > 45.0) CHECK(tile_directivity(k_a_sin) < 0.9);   // the tile matters there: the check can tell
    }
}

TEST_CASE("air push: DipoleRadiation plays each forced node's filter, and the modes below the crossover as they were") {
    const Canopy& built = air_canopy();
    const Point2 centroid = built.panel_centroid(0);
    const int node = built.locate(centroid.x, centroid.y).node;
    ListenerLayout layout;
    layout.points = {{1.0, 0.0, -0.3}};
    layout.channel_point = {0};
    Canopy off_canopy(built), on_canopy(built);
    DipoleRadiation off(off_canopy, layout, 1.0 / rate);
    DipoleRadiation on(on_canopy, layout, 1.0 / rate, AirMedium{}, DipoleOptions{.compressible_push = true});
    CHECK(off.push_filters(0) == nullptr);
    const PushFilters* f = on.push_filters(0);
    REQUIRE(f != nullptr);
    const PushCrossover x = push_crossover(*built.air_modes());

    // The forces a step took, per node: two on the struck node and one on another, summed.
    const int steps = 9600;
    std::vector<double> y_off(steps), y_on(steps), panel_forces(static_cast<std::size_t>(built.panel_count()));
    on_canopy.apply_force({0, node}, 0.6);
    on_canopy.apply_force({0, node}, 0.4);
    off_canopy.apply_force({0, node}, 1.0);
    CHECK(on_canopy.air_state().forced_nodes() == 0);   // gathered for the step, not yet taken
    int forced[2] = {-1, -1}, forced_node = -1;
    double forced_newtons = 0.0;
    test::RtAudit audit;
    {
        test::RtAudit::Scope scope;   // the steps and the push's playing: no allocation, lock or block
        for (int n = 0; n < steps; ++n) {
            on_canopy.step(panel_forces.data());
            off_canopy.step(panel_forces.data());
            if (n < 2) forced[n] = on_canopy.air_state().forced_nodes();
            if (n == 0) {
                forced_node = on_canopy.air_state().forced_node(0);
                forced_newtons = on_canopy.air_state().forced_newtons(0);
            }
            on.process(on_canopy, &y_on[static_cast<std::size_t>(n)]);
            off.process(off_canopy, &y_off[static_cast<std::size_t>(n)]);
        }
    }
    CHECK(audit.violations() == 0);
    CHECK(audit.entries() > 0);
    INFO(audit.first());
    CHECK(forced[0] == 1);   // the step took the struck node's forces, summed
    CHECK(forced_node == node);
    CHECK(forced_newtons == test::relative(1.0).epsilon(1e-15));
    CHECK(forced[1] == 0);   // and the next step none

    // What the push added is the node's filter, at its offset, to rounding: y_on - LP(y_off).
    LowPassState low;
    double worst = 0.0, largest = 0.0;
    const auto e = static_cast<std::size_t>(node);
    for (int n = 0; n < steps; ++n) {
        const double added = y_on[static_cast<std::size_t>(n)] - low.process(x, y_off[static_cast<std::size_t>(n)]);
        const int j = n - f->offset[e];
        const double expected = j >= 0 && j < f->taps ? f->fir[e * static_cast<std::size_t>(f->taps) + static_cast<std::size_t>(j)] : 0.0;
        worst = std::max(worst, std::abs(added - expected));
        largest = std::max(largest, std::abs(expected));
    }
    CHECK(largest > 0.0);
    CHECK(worst < 1e-9 * largest);

    // Below the crossover the band levels are the modes' (the low half is an all-pass there, the
    // filters' high half nothing): within 0.2 dB from 63 to 500 Hz over the 0.2 s. (The 63 Hz band, under
    // the lowest mode and 27 dB below its neighbours, holds what leaks from them through its skirts;
    // the all-pass's phase moves it by 0.13 dB. The others move by under 0.02 dB.)
    const std::vector<reference::BandLevel> a = reference::third_octave_levels(y_off, 1.0 / rate, 63.0, 500.0);
    const std::vector<reference::BandLevel> b = reference::third_octave_levels(y_on, 1.0 / rate, 63.0, 500.0);
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        INFO(a[k].centre_hz << " Hz");
        CHECK(std::abs(a[k].level_db - b[k].level_db) < (k == 0 ? 0.2 : 0.02));
    }
    // Where the halves overlap (the 1-1.6 kHz bands) the push joins the modes' own push, at the same
    // delay D, without a hole: within 2 dB of the modes alone. (At the struck node's own delay r / c,
    // 0.3 ms later here, the 1.26 kHz band fell 6.7 dB: air_push.hpp.)
    const std::vector<reference::BandLevel> c = reference::third_octave_levels(y_off, 1.0 / rate, 1000.0, 1600.0);
    const std::vector<reference::BandLevel> d = reference::third_octave_levels(y_on, 1.0 / rate, 1000.0, 1600.0);
    for (std::size_t k = 0; k < c.size(); ++k) {
        MESSAGE(c[k].centre_hz << " Hz: " << d[k].level_db - c[k].level_db << " dB with the push");
        CHECK(std::abs(d[k].level_db - c[k].level_db) < 2.0);
    }
}

}  // namespace ameoto
