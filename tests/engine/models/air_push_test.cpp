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
#include "engine/core/random.hpp"
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

// The point as the dipoles see it (r, cos(theta) per node), every node of areal density s, each node's
// push from its tile (the disc of its area) or, tiles false, a point.
PointView view(const Canopy& canopy, Vec3 listener, double s, bool tiles = true) {
    const AirCanopyModes& m = *canopy.air_modes();
    PointView v;
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            const Vec3 d = listener - canopy.rest_position(k, i);
            v.point.r.push_back(norm(d));
            v.point.cos_theta.push_back(dot(d, canopy.normal(k, i)) / norm(d));
            v.screen.areal_density.push_back(canopy.panel(k).network.mass(i) > 0.0 ? s : 0.0);
            const double area = m.node_area[static_cast<std::size_t>(k * canopy.nodes_per_panel() + i)];
            v.screen.tile_radius.push_back(tiles ? std::sqrt(area / constants::pi) : 0.0);
        }
    return v;
}

// A point force's dipole at hz from node i, heard at the view's point, its own delay r / c included:
// cos(theta) (1 / r^2 + i w / (c r)) e^{-i w r / c} (dipole_radiation.hpp, without the 1 / (4 pi)).
cplx dipole(const PointView& v, std::size_t i, double hz) {
    const double w = 2.0 * constants::pi * hz, c = constants::speed_of_sound_air, r = v.point.r[i];
    return v.point.cos_theta[i] * cplx(1.0 / (r * r), w / (c * r)) * std::polar(1.0, -w * r / c);
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

TEST_CASE("air push: the instantaneous push is M_a (M + M_a)^-1, the part of a newton the air takes at once") {
    // Built from the modes as (M_a Phi) Phi'. With the incompressible shapes (compressible_in_phase_ka 0)
    // it is checked on the moving nodes against I - M Phi Phi', which needs the structural masses instead
    // of the air's (Phi' (M + M_a) Phi = I with every mode kept). The default build's two moved in-phase
    // modes (air_canopy.hpp) carry their residue's shapes and the extra mass's force instead: the push is
    // the modes' own, so that the taps' kicks and the filters' push still cancel at DC (a steady force
    // makes no sound), and it differs from the identity by those two modes' terms alone.
    const Canopy& canopy = air_canopy();
    const AirCanopyModes& m = *canopy.air_modes();
    AirCanopyOptions incompressible;
    incompressible.compressible_in_phase_ka = 0.0;
    const auto plain_modes = build_air_canopy_modes(canopy, 1.0 / rate, incompressible);
    const AirCanopyModes& plain = *plain_modes;
    REQUIRE(m.modes == m.modes_found);
    REQUIRE(plain.modes == m.modes);
    REQUIRE(m.instantaneous_push.rows() == m.nodes);
    REQUIRE(m.instantaneous_push.cols() == m.nodes);
    const Point2 centroid = canopy.panel_centroid(0);
    const int e = canopy.locate(centroid.x, centroid.y).node;
    const int per_panel = canopy.nodes_per_panel();
    const auto shape = [](const AirCanopyModes& modes, int i, int k) { return modes.shape[static_cast<std::size_t>(i * modes.modes + k)]; };
    std::vector<int> moved;
    for (int k = 0; k < m.modes; ++k)
        if (m.omega[k] != plain.omega[k]) moved.push_back(k);
    CHECK(moved.size() == 2);
    double worst = 0.0, worst_moved = 0.0, total = 0.0, plain_total = 0.0;
    for (int i = 0; i < m.nodes; ++i) {
        const double mass = canopy.panel(i / per_panel).network.mass(i % per_panel);
        total += m.instantaneous_push(i, e);
        plain_total += plain.instantaneous_push(i, e);
        double change = 0.0;   // the moved modes' terms
        for (const int k : moved) change += m.air_force(i, k) * shape(m, e, k) - plain.air_force(i, k) * shape(plain, e, k);
        worst_moved = std::max(worst_moved, std::abs(m.instantaneous_push(i, e) - plain.instantaneous_push(i, e) - change));
        if (!(mass > 0.0)) continue;   // a node that cannot move: no identity for its row
        double mobility = 0.0;
        for (int k = 0; k < plain.modes; ++k) mobility += shape(plain, i, k) * shape(plain, e, k);
        worst = std::max(worst, std::abs(plain.instantaneous_push(i, e) - ((i == e ? 1.0 : 0.0) - mass * mobility)));
    }
    const double own = m.instantaneous_push(e, e);
    MESSAGE("a newton on node " << e << ": " << own * 100.0 << " % on the node, " << total * 100.0 << " % on the air in all ("
                                << plain_total * 100.0 << " % with the incompressible shapes)");
    CHECK(worst < 1e-9);
    CHECK(worst_moved < 1e-9);
    // The air next to a light fabric takes most of a newton at once (air_canopy.hpp's figures).
    CHECK(own == doctest::Approx(0.38).epsilon(0.1));
    CHECK(plain_total == doctest::Approx(0.92).epsilon(0.05));
    CHECK(total == doctest::Approx(0.80).epsilon(0.05));
}

TEST_CASE("air push: a node's filter is its instantaneous push through the low half and its tile's compressible push through the high") {
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
    const double r = v.point.r[e], cos_theta = v.point.cos_theta[e], lag = r / c;
    const double a = v.screen.tile_radius[e], sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
    INFO("r " << r << " m, cos(theta) " << cos_theta << ", r / c = " << lag * 1e3 << " ms, tile radius " << a << " m");
    REQUIRE(a > 0.02);   // the centroid's tile: about a 50th of the panel's 0.088 m^2
    REQUIRE(a < 0.03);
    CHECK(f.offset[e] == static_cast<int>(std::floor(lag * rate)) - 24);   // from 0.5 ms before its own delay

    // Low: each node's share of the instantaneous push (its column) as a point force at its own delay;
    // high: f / (1 + i beta |cos(theta)|) from the node's tile at its own delay; the force held over the
    // step. Within 1 % from 100 Hz to 12 kHz.
    auto expected = [&](double hz) {
        const double w = 2.0 * constants::pi * hz;
        const double beta = w * s / (2.0 * rho * c);
        const cplx held = (std::polar(1.0, w / rate) - 1.0) / cplx(0.0, w / rate);
        cplx column = 0.0;
        for (std::size_t i = 0; i < v.point.r.size(); ++i)
            column += m.instantaneous_push(static_cast<Eigen::Index>(i), node) * dipole(v, i, hz);
        const cplx push = dipole(v, e, hz) / cplx(1.0, beta * std::abs(cos_theta)) *
                          (2.0 * std::cyl_bessel_j(1.0, w / c * a * sin_theta) / (w / c * a * sin_theta));
        return held / (4.0 * constants::pi) * (half_response(x.low, hz) * column + half_response(x.high, hz) * push);
    };
    for (double hz : {100.0, 250.0, 500.0, 0.8 * x.hz, x.hz, 1.25 * x.hz, 1.5e3, 2.5e3, 3.0e3, 4.0e3, 6.0e3, 8.0e3, 12.0e3}) {
        const cplx want = expected(hz), got = filter_response(f, e, hz);
        INFO(hz << " Hz: " << got << " against " << want);
        CHECK(std::abs(got - want) < 0.01 * std::abs(want));
    }
    // Above the crossover the push comes at the node's own delay r / c: the phase's slope less the high
    // half's, the near field's and the jump's is r / c, within 2 us.
    for (double hz : {3000.0, 4000.0}) {
        const double dh = 2.0;
        const double slope = -std::arg(filter_response(f, e, hz + dh) / filter_response(f, e, hz - dh)) / (2.0 * constants::pi * 2.0 * dh);
        const double own = -std::arg(half_response(x.high, hz + dh) / half_response(x.high, hz - dh)) / (2.0 * constants::pi * 2.0 * dh);
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
    // 6 kHz, 3 m away, on a 5 kg/m^2 screen (beta = 220): within 5 % (the near field, 1 / kr = 0.003,
    // 1 / beta, and the low half's instantaneous push, 115 dB down there), at 25 and 70 degrees from the
    // normal, for a point (tile radius 0); the node's tile takes its disc's directivity off it, the same 5 %.
    const Canopy& canopy = air_canopy();
    const AirCanopyModes& m = *canopy.air_modes();
    const PushCrossover x = push_crossover(m);
    const double s = 5.0, hz = 6000.0;
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

TEST_CASE("air push: three taps a mode are exact at the mode's pole and at DC") {
    // p = A x[n] + B x[n-1] + C x[n-2] for x = Re(X z^-n): on the pole's motion (z = e^{lambda T}) the
    // taps give Re(total X z^-n) with A + B z1 + C z1^2 = total, z1 = e^{-lambda T}; on a constant, dc.
    Random rng(5);
    for (int trial = 0; trial < 200; ++trial) {
        const double hz = std::exp(rng.uniform(std::log(20.0), std::log(15000.0))), s = rng.uniform(0.1, 300.0);
        const double w_t = 2.0 * constants::pi * hz / rate, s_t = s / rate;
        const cplx total(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        const double dc = rng.uniform(-1.0, 1.0);
        const DipoleTaps d = dipole_taps_three(total, s_t, w_t, dc);
        const cplx z1 = std::polar(std::exp(s_t), -w_t);
        const cplx got = d.a + d.b * z1 + d.c * z1 * z1;
        const double size = std::abs(d.a) + std::abs(d.b) + std::abs(d.c);
        INFO(hz << " Hz, " << s << " /s: " << got << " against " << total << "; A + B + C " << d.a + d.b + d.c << " against " << dc);
        CHECK(std::abs(got - total) < 1e-12 * size);
        CHECK(std::abs(d.a + d.b + d.c - dc) < 1e-12 * size);
    }
    // Two taps: exact at the pole only.
    const cplx z1 = std::polar(std::exp(10.0 / rate), -2.0 * constants::pi * 100.0 / rate);
    const DipoleTaps two = dipole_taps_two(cplx(0.3, -0.2), z1);
    CHECK(std::abs(two.a + two.b * z1 - cplx(0.3, -0.2)) < 1e-12);
    CHECK(two.c == 0.0);
}

TEST_CASE("air push: the three taps on abar - kick are a dot with the mode's state and its last two kicks") {
    // One mode stepped as AirCanopyState steps it (kick, then the exact transition), kicked now and then:
    // A x[n] + B x[n-1] + C x[n-2] with x = abar - kick, against dipole_state_taps' four terms.
    Random rng(9);
    for (double hz : {84.6, 400.0, 962.6, 5000.0}) {
        const double w = 2.0 * constants::pi * hz, s = 7.4, t = 1.0 / rate;
        const double wd = std::sqrt(w * w - s * s), e = std::exp(-s * t), ec = e * std::cos(wd * t), es = e * std::sin(wd * t) / wd;
        const double t11 = ec + s * es, t12 = es, t21 = -w * w * es, t22 = ec - s * es;   // mode_decay.hpp's transition
        const DipoleTaps three = dipole_taps_three(cplx(0.02, -0.01), s * t, wd * t, 0.005);
        const StateTaps state = dipole_state_taps(three, t11, t12, t21, t22, t);
        double q = 0.0, qd = 0.0, x1 = 0.0, x2 = 0.0, kick_before = 0.0, worst = 0.0, largest = 0.0;
        for (int n = 0; n < 4000; ++n) {
            const double p = (n % 97 < 3 || (n > 2000 && n < 2400)) ? rng.uniform(-1e3, 1e3) : 0.0;   // single kicks, and a long force
            const double kicked = qd + t * p;
            const double q_next = t11 * q + t12 * kicked, qd_next = t21 * q + t22 * kicked;
            const double x0 = (qd_next - qd) / t - p;
            q = q_next;
            qd = qd_next;
            const double taps = three.a * x0 + three.b * x1 + three.c * x2;
            const double dot = state.q * q + state.qd * qd + state.kick * p + state.kick_before * kick_before;
            worst = std::max(worst, std::abs(taps - dot));
            largest = std::max(largest, std::abs(taps));
            x2 = x1;
            x1 = x0;
            kick_before = p;
        }
        INFO(hz << " Hz: worst " << worst << " of " << largest);
        CHECK(largest > 0.0);
        CHECK(worst < 1e-9 * largest);
    }
}

TEST_CASE("air push: DipoleRadiation plays the modes less their kicks through three taps and the low half, and each forced node's filter") {
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
    CHECK_FALSE(off.state_taps());
    CHECK(on.state_taps());
    const PushFilters* f = on.push_filters(0);
    REQUIRE(f != nullptr);
    const PushCrossover x = push_crossover(*built.air_modes());
    const int modes = on.modes();

    // The forces a step took, per node: two on the struck node and one on another, summed; a second
    // force later, while the modes ring.
    const int steps = 9600;
    std::vector<double> y_on(steps), y_off(steps), panel_forces(static_cast<std::size_t>(built.panel_count()));
    // Each step's state, rows of 2 x modes: q, q'.
    std::vector<std::vector<double>> heard(static_cast<std::size_t>(steps), std::vector<double>(2 * static_cast<std::size_t>(modes)));
    on_canopy.apply_force({0, node}, 0.6);
    on_canopy.apply_force({0, node}, 0.4);
    off_canopy.apply_force({0, node}, 1.0);
    CHECK(on_canopy.air_state().forced_nodes() == 0);   // gathered for the step, not yet taken
    int forced[2] = {-1, -1}, forced_node = -1;
    double forced_newtons = 0.0;
    test::RtAudit audit;
    {
        test::RtAudit::Scope scope;   // the steps, the taps and the push's playing: no allocation, lock or block
        for (int n = 0; n < steps; ++n) {
            if (n == 3000) on_canopy.apply_force({0, node}, -0.5);
            on_canopy.step(panel_forces.data());
            off_canopy.step(panel_forces.data());
            if (n < 2) forced[n] = on_canopy.air_state().forced_nodes();
            if (n == 0) {
                forced_node = on_canopy.air_state().forced_node(0);
                forced_newtons = on_canopy.air_state().forced_newtons(0);
            }
            on.process(on_canopy, &y_on[static_cast<std::size_t>(n)]);
            off.process(off_canopy, &y_off[static_cast<std::size_t>(n)]);
            const AirCanopyState& st = on_canopy.air_state();
            auto& row = heard[static_cast<std::size_t>(n)];
            std::copy(st.modal_q(), st.modal_q() + modes, row.begin());
            std::copy(st.modal_qd(), st.modal_qd() + modes, row.begin() + modes);
        }
    }
    CHECK(audit.violations() == 0);
    CHECK(audit.entries() > 0);
    INFO(audit.first());
    CHECK(forced[0] == 1);   // the step took the struck node's forces, summed
    CHECK(forced_node == node);
    CHECK(forced_newtons == test::relative(1.0).epsilon(1e-15));
    CHECK(forced[1] == 0);   // and the next step none

    // The output, rebuilt here: the taps on the state and on the struck node's forces, now and a step
    // before (the three taps on abar - kick), through the low half at D, and the node's filter at its
    // offset; to rounding.
    LowPassState low;
    std::vector<double> rebuilt(static_cast<std::size_t>(steps), 0.0);
    const int delay = on.delay_samples(0);
    auto newtons = [](int n) { return n == 0 ? 1.0 : n == 3000 ? -0.5 : 0.0; };
    for (int n = 0; n < steps; ++n) {
        double p = 0.0;
        const auto& now = heard[static_cast<std::size_t>(n)];
        for (int k = 0; k < modes; ++k) {
            const auto i = static_cast<std::size_t>(k), m = static_cast<std::size_t>(modes);
            p += on.tap(0, k, 0) * now[i] + on.tap(0, k, 1) * now[m + i];
        }
        p += on.tap(0, node, 2) * newtons(n) + on.tap(0, node, 3) * (n > 0 ? newtons(n - 1) : 0.0);
        if (n + delay < steps) rebuilt[static_cast<std::size_t>(n + delay)] += low.process(x, p);
    }
    const auto e = static_cast<std::size_t>(node);
    for (const auto& [start, newtons] : {std::pair<int, double>{0, 1.0}, std::pair<int, double>{3000, -0.5}})
        for (int j = 0; j < f->taps; ++j)
            if (start + f->offset[e] + j < steps)
                rebuilt[static_cast<std::size_t>(start + f->offset[e] + j)] += newtons * f->fir[e * static_cast<std::size_t>(f->taps) + static_cast<std::size_t>(j)];
    double worst = 0.0, largest = 0.0;
    for (int n = 0; n < steps; ++n) {
        worst = std::max(worst, std::abs(y_on[static_cast<std::size_t>(n)] - rebuilt[static_cast<std::size_t>(n)]));
        largest = std::max(largest, std::abs(rebuilt[static_cast<std::size_t>(n)]));
    }
    CHECK(largest > 0.0);
    CHECK(worst < 1e-9 * largest);
    // The forces' taps are the kicks' taken through the shapes, tap 2 = sum_k c_k phi_k(node): the node
    // taps of two nodes differ, and a node that cannot move has none.
    CHECK(on.tap(0, node, 2) != 0.0);
    CHECK(on.tap(0, node, 3) != 0.0);
    for (int i = 0; i < built.nodes_per_panel(); ++i)
        if (!(built.panel(0).network.mass(i) > 0.0)) {
            CHECK(on.tap(0, i, 2) == 0.0);
            CHECK(on.tap(0, i, 3) == 0.0);
            break;
        }

    // Without the push the taps are two a mode on abar, as before. Once the force is gone the modes ring
    // freely and both sets of taps are exact on that ring (at each mode's pole): from 10 ms (the push's
    // filter has played) to 60 ms (before the second force) the push's output less its filter is the
    // two taps' output through the low half, to rounding: 1e-6 of it (7e-8 measured), since the lowest
    // modes' three taps are about 60 times their two (exact at DC as well: A + B + C is a small sum of
    // large terms) and the two taps' kick is a spike 2 000 times the ring that the low half rounds.
    LowPassState low_off;
    double tail_worst = 0.0, tail_largest = 0.0;
    for (int n = 0; n < 2880; ++n) {
        const double expected = low_off.process(x, y_off[static_cast<std::size_t>(n)]);
        if (n < 480) continue;
        const int j = n - f->offset[e];
        const double filter = j >= 0 && j < f->taps ? f->fir[e * static_cast<std::size_t>(f->taps) + static_cast<std::size_t>(j)] : 0.0;
        tail_worst = std::max(tail_worst, std::abs(y_on[static_cast<std::size_t>(n)] - filter - expected));
        tail_largest = std::max(tail_largest, std::abs(expected));
    }
    CHECK(tail_largest > 0.0);
    CHECK(tail_worst < 1e-6 * tail_largest);
}

TEST_CASE("air push: a sibling's push filters are shared where designed alike, and the sound is the same bit for bit") {
    const Canopy& built = air_canopy();
    const Point2 centroid = built.panel_centroid(0);
    const int node = built.locate(centroid.x, centroid.y).node;
    ListenerLayout layout, other;
    layout.points = {{1.0, 0.0, -0.3}, {0.0, 0.0, -3.0}};
    layout.channel_point = {0, 1};
    other.points = {{0.0, 0.0, -3.0}, {0.5, 0.5, -1.0}};   // its first point is layout's second
    other.channel_point = {0, 1};
    const DipoleOptions push{.compressible_push = true};
    Canopy a_canopy(built), b_canopy(built), c_canopy(built), d_canopy(built);
    DipoleRadiation alone(a_canopy, layout, 1.0 / rate, AirMedium{}, push);
    DipoleRadiation shared(b_canopy, layout, 1.0 / rate, AirMedium{}, push, &alone);
    DipoleRadiation partly(c_canopy, other, 1.0 / rate, AirMedium{}, push, &alone);
    // Another air (a warmer day's speed of sound) designs its own, as does a canopy whose modes are another build.
    DipoleRadiation warmer(d_canopy, layout, 1.0 / rate, AirMedium{constants::air_density, 350.0}, push, &alone);
    Canopy rebuilt(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / rate);
    rebuilt.set_air(build_air_canopy_modes(rebuilt, 1.0 / rate));
    DipoleRadiation own_modes(rebuilt, layout, 1.0 / rate, AirMedium{}, push, &alone);
    REQUIRE(alone.push_filters(1) != nullptr);
    CHECK(shared.push_filters(0) == alone.push_filters(0));   // the same object
    CHECK(shared.push_filters(1) == alone.push_filters(1));
    CHECK(partly.push_filters(0) == alone.push_filters(1));
    CHECK(partly.push_filters(1) != alone.push_filters(0));
    CHECK(partly.push_filters(1) != alone.push_filters(1));
    CHECK(warmer.push_filters(0) != alone.push_filters(0));
    CHECK(own_modes.push_filters(0) != alone.push_filters(0));
    // A filter designed anew from equal inputs is the shared one, bit for bit.
    const PushFilters& mine = *own_modes.push_filters(0);
    const PushFilters& theirs = *alone.push_filters(0);
    CHECK(mine.offset == theirs.offset);
    CHECK(mine.fir == theirs.fir);
    // Played: the same samples from the two, a force on the centroid and the modes ringing.
    std::vector<double> panel_forces(static_cast<std::size_t>(built.panel_count()));
    a_canopy.apply_force({0, node}, 1.0);
    b_canopy.apply_force({0, node}, 1.0);
    bool same = true;
    double largest = 0.0;
    for (int n = 0; n < 2400; ++n) {
        a_canopy.step(panel_forces.data());
        b_canopy.step(panel_forces.data());
        double pa[2], pb[2];
        alone.process(a_canopy, pa);
        shared.process(b_canopy, pb);
        same = same && pa[0] == pb[0] && pa[1] == pb[1];
        largest = std::max(largest, std::abs(pa[1]));
    }
    CHECK(largest > 0.0);
    CHECK(same);
}

}  // namespace ameoto
