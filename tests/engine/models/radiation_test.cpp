// Tests for engine/models/radiation: the seed's single-mass output and the Rayleigh far field.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/models/radiation.hpp"
#include "tests/support/rt_probe_scope.hpp"

using ameoto::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kT = 1.0 / 48000.0;
constexpr double kRho = ameoto::constants::air_density, kC = ameoto::constants::speed_of_sound_air;

// Runs a radiator over an acceleration sequence for one element set; returns out[point * groups + group]
// per sample.
std::vector<std::vector<double>> run(ameoto::RayleighRadiator& r, const std::vector<std::vector<double>>& a) {
    std::vector<std::vector<double>> out;
    std::vector<double> o(static_cast<std::size_t>(r.point_count() * r.group_count()));
    for (const auto& frame : a) {
        r.process(frame.data(), o.data());
        out.push_back(o);
    }
    return out;
}

double rms(const std::vector<double>& x) {
    double s = 0.0;
    for (double v : x) s += v * v;
    return std::sqrt(s / static_cast<double>(x.size()));
}

}  // namespace

TEST_CASE("radiation: one element's impulse arrives as rho0 A a / (2 pi r), delayed by r / c") {
    const double area = 2e-3, a0 = 3.7;
    SUBCASE("integer delay: exact to rounding") {
        const double r = kC * 24.0 * kT;   // 0.1715 m: 24 samples
        ameoto::RayleighRadiator rad({{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, area, 0}}, {{0.0, 0.0, r}, {0.0, 0.0, -r}}, 1, kT);
        std::vector<std::vector<double>> a(60, std::vector<double>{0.0});
        a[5][0] = a0;
        const auto out = run(rad, a);
        const double expected = kRho * area * a0 / (2.0 * kPi * r);   // radiation.hpp
        CHECK(rad.delay_samples(0, 0) == doctest::Approx(24.0).epsilon(1e-14));
        for (std::size_t n = 0; n < out.size(); ++n) {
            CAPTURE(n);
            if (n == 29) {
                CHECK(out[n][0] == doctest::Approx(expected).epsilon(1e-14));
                CHECK(out[n][1] == doctest::Approx(-expected).epsilon(1e-14));   // the other face: -a
            } else {
                CHECK(std::abs(out[n][0]) <= 1e-14 * expected);
                CHECK(std::abs(out[n][1]) <= 1e-14 * expected);
            }
        }
    }
    SUBCASE("fractional delay: linear interpolation between the two neighbouring samples") {
        const double r = kC * 24.3 * kT;
        ameoto::RayleighRadiator rad({{{0.1, 0.2, 0.0}, {0.0, 0.0, 1.0}, area, 0}}, {{0.1, 0.2 + r, 0.0}}, 1, kT);
        std::vector<std::vector<double>> a(60, std::vector<double>{0.0});
        a[0][0] = a0;
        const auto out = run(rad, a);
        const double g = kRho * area * a0 / (2.0 * kPi * r);   // the point lies in the plane: side +
        CHECK(out[24][0] == doctest::Approx(0.7 * g).epsilon(1e-12));
        CHECK(out[25][0] == doctest::Approx(0.3 * g).epsilon(1e-12));
        double total = 0.0;
        for (const auto& o : out) total += o[0];
        CHECK(total == doctest::Approx(g).epsilon(1e-14));   // the interpolation keeps the area
    }
    SUBCASE("a listening point on the element: the disc's own integral rho0 a a_eq") {
        ameoto::RayleighRadiator rad({{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, area, 0}}, {{0.0, 0.0, 0.0}}, 1, kT);
        CHECK(rad.gain(0, 0) == doctest::Approx(kRho * std::sqrt(area / kPi)).epsilon(1e-14));
    }
}

TEST_CASE("radiation: with every r_i equal the sum is the renderer's rho0 F_net / (2 pi r s)") {
    // The panel of the default nylon canopy, its nodes rearranged on a sphere of radius r around the
    // listening point (all r_i = r, all facing it): radiation.hpp says sum A_i a_i = F_net / s exactly,
    // with a_i the step's mean acceleration; F_net is what the renderer radiates (renderer.hpp).
    ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    const int nodes = canopy.nodes_per_panel();
    const double r = kC * 30.0 * kT;
    std::vector<ameoto::RadiatingElement> elements;
    for (int i = 0; i < nodes; ++i) {
        const double th = 0.3 + 0.02 * i, ph = 0.37 * i;
        const Vec3 dir{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
        elements.push_back({r * dir, -1.0 * dir, canopy.node_area(), 0});
    }
    ameoto::RayleighRadiator rad(elements, {{0.0, 0.0, 0.0}}, 1, kT);
    std::vector<double> panel_forces(8), v_prev(static_cast<std::size_t>(nodes), 0.0), a(static_cast<std::size_t>(nodes));
    std::vector<double> f_net, p;
    double out = 0.0;
    for (int n = 0; n < 600; ++n) {
        if (n < 20) canopy.apply_force({0, 11}, 0.3);
        if (n == 40) canopy.apply_force({0, 30}, -2.0);
        canopy.step(panel_forces.data());
        for (int i = 0; i < nodes; ++i) {
            const double v = canopy.normal_velocity(0, i);
            a[static_cast<std::size_t>(i)] = (v - v_prev[static_cast<std::size_t>(i)]) / kT;
            v_prev[static_cast<std::size_t>(i)] = v;
        }
        rad.process(a.data(), &out);
        f_net.push_back(panel_forces[0]);
        p.push_back(out);
    }
    const double s = canopy.panel(0).material.areal_density;
    double peak = 0.0, worst = 0.0;
    for (std::size_t n = 30; n < p.size(); ++n) {
        const double expected = kRho * f_net[n - 30] / (2.0 * kPi * r * s);
        peak = std::max(peak, std::abs(expected));
        worst = std::max(worst, std::abs(p[n] - expected));
    }
    for (std::size_t n = 0; n < 30; ++n) CHECK(p[n] == 0.0);   // nothing before r / c
    REQUIRE(peak > 0.0);
    CHECK(worst <= 1e-12 * peak);   // rounding
}

TEST_CASE("radiation: the canopy's far field tends to the renderer's panel piston far away") {
    // A listener 50 m below the flat canopy's centre: all r_i within R^2 / (2 r) = 2.5 mm of each
    // other (0.35 samples), so the per-element sum must match rho0 F_net / (2 pi r s) summed over the
    // panels, delayed by the mean r / c, to within the effect of the remaining path differences (the
    // struck node's 2.5 mm against the 0.3 m wavelength of the panel's top mode: about 1 %; measured
    // 0.50 %, and 0.15 % at 150 m: it falls like 1 / r, as the far-field limit should).
    ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    const double depth = 50.0;
    ameoto::FarFieldRadiation ff(canopy, ameoto::ListenerLayout::mono({0.0, 0.0, -depth}), kT);
    std::vector<double> forces(8), p, net;
    double out = 0.0;
    const int samples = 9600;
    for (int n = 0; n < samples; ++n) {
        if (n < 40) canopy.apply_force({2, 11}, 0.3 * std::pow(std::sin(kPi * (n + 0.5) / 40.0), 2));   // smooth push
        canopy.step(forces.data());
        ff.process(canopy, &out);
        double sum = 0.0;
        for (double f : forces) sum += f;
        net.push_back(sum);
        p.push_back(out);
    }
    // Reference delay: the elements' mean (all areas equal), 0.18 samples beyond the centre's r / c.
    double delay = 0.0;
    for (int e = 0; e < ff.radiator().element_count(); ++e) delay += ff.radiator().delay_samples(0, e);
    delay /= ff.radiator().element_count();
    const double s = 0.06;
    const auto d0 = static_cast<std::size_t>(std::floor(delay));
    std::vector<double> diff, ref;
    for (std::size_t n = d0 + 2; n < p.size(); ++n) {
        // Listener below: it faces -n, so it hears -a (radiation.hpp); interpolate the reference delay.
        const double frac = delay - std::floor(delay);
        const double f = (1.0 - frac) * net[n - d0] + frac * net[n - d0 - 1];
        const double expected = -kRho * f / (2.0 * kPi * depth * s);
        ref.push_back(expected);
        diff.push_back(p[n] - expected);
    }
    CHECK(rms(diff) <= 0.01 * rms(ref));
    MESSAGE("far field vs panel piston at 50 m: relative RMS difference " << rms(diff) / rms(ref));
}

TEST_CASE("radiation: two ears hear the inter-aural delay and level from the geometry") {
    ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    const auto layout = ameoto::ListenerLayout::ears({0.0, 0.0, -0.3}, 0.0, 0.18);
    REQUIRE(layout.channels() == 2);
    CHECK(layout.points[0].y == doctest::Approx(0.09).epsilon(1e-15));    // left ear: +y when facing +x
    CHECK(layout.points[1].y == doctest::Approx(-0.09).epsilon(1e-15));
    ameoto::FarFieldRadiation ff(canopy, layout, kT);
    // Panel 2 is at azimuth 90 degrees: on the listener's left.
    const auto& rad = ff.radiator();
    const int node = 20, e = 2 * canopy.nodes_per_panel() + node;
    const Vec3 x = canopy.rest_position(2, node);
    CHECK(rad.distance(0, e) == doctest::Approx(ameoto::norm(x - layout.points[0])).epsilon(1e-14));
    CHECK(rad.delay_samples(0, e) == doctest::Approx(rad.distance(0, e) / kC / kT).epsilon(1e-14));
    CHECK(rad.delay_samples(0, e) < rad.delay_samples(1, e));
    // Strike it: the left channel's first arrival leads the right one's, and it is louder.
    std::vector<double> forces(8);
    double out[2];
    int first[2] = {-1, -1};
    double energy[2] = {0.0, 0.0};
    canopy.apply_force({2, node}, 0.5);
    for (int n = 0; n < 4800; ++n) {
        canopy.step(forces.data());
        ff.process(canopy, out);
        for (int c = 0; c < 2; ++c) {
            if (first[c] < 0 && std::abs(out[c]) > 0.0) first[c] = n;
            energy[c] += out[c] * out[c];
        }
    }
    CHECK(first[0] >= 0);
    CHECK(first[0] < first[1]);
    CHECK(energy[0] > energy[1]);
    // The struck node moves in the first step, its neighbours from the next (explicit scheme), so the
    // first arrival is no later than the struck node's delay and no earlier than the nearest node's.
    for (int c = 0; c < 2; ++c) {
        double nearest = 1e9;
        for (int i = 0; i < rad.element_count(); ++i) nearest = std::min(nearest, rad.delay_samples(c, i));
        CHECK(first[c] <= static_cast<int>(std::floor(rad.delay_samples(c, e))));
        CHECK(first[c] >= static_cast<int>(std::floor(nearest)));
    }
}

TEST_CASE("radiation: a panned layout is the mono point weighted per panel") {
    ameoto::Canopy a(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    ameoto::Canopy b(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    const Vec3 at{0.0, 0.0, -0.3};
    std::vector<std::vector<double>> gains(4, std::vector<double>(8, 0.0));
    for (int c = 0; c < 4; ++c) gains[static_cast<std::size_t>(c)][static_cast<std::size_t>(2 * c)] = 1.0;
    ameoto::FarFieldRadiation ring(a, ameoto::ListenerLayout::panned(at, gains), kT);
    // Mono per panel: panel k alone is the mono pressure of a canopy where only panel k moves.
    ameoto::FarFieldRadiation mono(b, ameoto::ListenerLayout::mono(at), kT);
    std::vector<double> forces(8);
    double ring_out[4], mono_out = 0.0;
    for (int n = 0; n < 2000; ++n) {
        if (n < 10) {
            a.apply_force({4, 12}, 0.2);   // panel 4: channel 2 only
            b.apply_force({4, 12}, 0.2);
        }
        a.step(forces.data());
        b.step(forces.data());
        ring.process(a, ring_out);
        mono.process(b, &mono_out);
        CHECK(ring_out[0] == 0.0);
        CHECK(ring_out[1] == 0.0);
        CHECK(ring_out[2] == doctest::Approx(mono_out).epsilon(1e-12));
        CHECK(ring_out[3] == 0.0);
    }
    CHECK_THROWS_AS(ameoto::FarFieldRadiation(a, ameoto::ListenerLayout::panned(at, {{1.0, 2.0}}), kT),
                    std::invalid_argument);
}

TEST_CASE("radiation: every material renders finite, non-silent sound, far field and single mass") {
    // A 2 mm drop at terminal speed (6.49 m/s, Gunn & Kinzer) delivers m V in one step on a mid-panel
    // node of each preset (seed-nylon with its 27 sub-steps) and of a custom material; 0.2 s rendered.
    // Non-silent: the far field's peak above 1e-4 of the renderer's 40 Pa full scale (-80 dBFS) and the
    // pickup's above 1e-3 of its default full scale (-60 dBFS), both far above 24-bit resolution (6e-8).
    const double drop_mass = ameoto::constants::water_density * kPi / 6.0 * 8e-9, v = 6.49;
    std::vector<ameoto::MembraneMaterial> materials;
    for (const auto& n : ameoto::membrane_material_names()) materials.push_back(*ameoto::membrane_material(n));
    materials.push_back(ameoto::MembraneMaterial::custom("drumhead", 0.3, 3000.0, 5.0, 1e-6));
    static bool printed = false;
    const bool print = std::getenv("AMEOTO_PRINT_TABLES") != nullptr && !printed;
    printed = true;
    if (print) std::printf("\n| material | sub-steps | far-field peak L, R (Pa) | pickup peak (m) |\n|---|---|---|---|\n");
    for (const auto& m : materials) {
        CAPTURE(m.name);
        ameoto::Canopy canopy(ameoto::CanopyGeometry{8, 0.5, 50, 1.5}, m, kT);
        ameoto::FarFieldRadiation ff(canopy, ameoto::ListenerLayout::ears({0.0, 0.0, -0.4}), kT);
        const auto pick = ameoto::MassPickup::at(canopy, 0.2, 0.05);
        const auto hit = canopy.locate(0.2, 0.05);
        std::vector<double> forces(8);
        double out[2], peak[2] = {0.0, 0.0}, pick_peak = 0.0;
        bool finite = true;
        canopy.apply_force(hit, -drop_mass * v / kT);   // down, against n
        for (int n = 0; n < 9600; ++n) {
            canopy.step(forces.data());
            ff.process(canopy, out);
            const double u = pick.sample(canopy);
            finite = finite && std::isfinite(out[0]) && std::isfinite(out[1]) && std::isfinite(u);
            peak[0] = std::max(peak[0], std::abs(out[0]));
            peak[1] = std::max(peak[1], std::abs(out[1]));
            pick_peak = std::max(pick_peak, std::abs(u));
        }
        CHECK(finite);
        CHECK(peak[0] > 40.0 * 1e-4);
        CHECK(peak[1] > 40.0 * 1e-4);
        CHECK(pick_peak > 1e-3);
        CHECK(pick_peak < 1.0);
        CHECK(canopy.reset_unstable() == 0);
        if (print)
            std::printf("| %s | %d | %.3g, %.3g | %.3g |\n", m.name.c_str(), canopy.panel(0).network.stability().sub_steps,
                        peak[0], peak[1], pick_peak * pick.full_scale_m());
    }
}

TEST_CASE("radiation: a panel reset by the guard is heard from rest, and the output stays finite") {
    ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    ameoto::FarFieldRadiation ff(canopy, ameoto::ListenerLayout::mono({0.0, 0.0, -0.3}), kT);
    std::vector<double> forces(8);
    double out = 0.0;
    canopy.apply_force({3, 10}, 0.5);
    for (int n = 0; n < 100; ++n) {
        canopy.step(forces.data());
        ff.process(canopy, &out);
    }
    canopy.apply_force({3, 10}, std::numeric_limits<double>::infinity());
    canopy.step(forces.data());
    ff.process(canopy, &out);
    CHECK(std::isfinite(out));   // non-finite accelerations count as 0 (radiation.hpp)
    CHECK(canopy.reset_unstable() == 1);
    double peak = 0.0;
    for (int n = 0; n < 200; ++n) {
        canopy.step(forces.data());
        ff.process(canopy, &out);
        CHECK(std::isfinite(out));
        if (n > 100) peak = std::max(peak, std::abs(out));   // after the delay lines drained (82 samples)
    }
    // Panel 3 restarted from rest, every other panel was never struck: silence, not a click.
    CHECK(peak == 0.0);
}

TEST_CASE("radiation: process and sample never allocate") {
    ameoto::Canopy canopy(ameoto::CanopyGeometry{8, 0.5, 50, 1.5}, ameoto::MembraneMaterial::vinyl(), kT);
    ameoto::FarFieldRadiation ff(canopy, ameoto::ListenerLayout::ears({0.0, 0.0, -0.3}), kT);
    const ameoto::MassPickup pick(canopy, 1, 7);
    std::vector<double> forces(8);
    double out[2], sum = 0.0;
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope s;
        for (int n = 0; n < 500; ++n) {
            if (n % 50 == 0) canopy.apply_force({n % 8, n % 40}, -0.1);
            canopy.step(forces.data());
            ff.process(canopy, out);
            sum += out[0] + out[1] + pick.sample(canopy);
        }
    }
    CHECK(std::isfinite(sum));
    CHECK(audit.entries() > 0);
    CHECK(audit.violations() == 0);
    CHECK(audit.first() == "none");
}

TEST_CASE("radiation: bad arguments are refused") {
    ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    CHECK_THROWS_AS(ameoto::MassPickup(canopy, 8, 0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::MassPickup(canopy, 0, 500), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::MassPickup(canopy, 0, 0, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    // Default full scale: 10 N over the node's stiffness (an interior nylon node: 6 links of 1000 / sqrt 3 N/m).
    int interior = -1;
    for (int i = 0; i < canopy.nodes_per_panel() && interior < 0; ++i) {
        int links = 0;
        for (const auto& l : canopy.panel(0).lattice.links) links += (l.a == i || l.b == i);
        if (links == 6) interior = i;
    }
    REQUIRE(interior >= 0);
    CHECK(ameoto::MassPickup(canopy, 0, interior).full_scale_m() == doctest::Approx(10.0 / (6.0 * 1000.0 / std::sqrt(3.0))).epsilon(1e-12));
    CHECK(ameoto::MassPickup(canopy, 0, interior, 1e-3).full_scale_m() == 1e-3);
    CHECK_THROWS_AS(ameoto::MassPickup::at(canopy, 2.0, 0.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::FarFieldRadiation(canopy, ameoto::ListenerLayout{}, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::RayleighRadiator({}, {}, 1, kT), std::invalid_argument);
    // A canopy of another shape is not read (radiation.hpp): silence, no out-of-range access.
    ameoto::FarFieldRadiation ff(canopy, ameoto::ListenerLayout::mono({0.0, 0.0, -0.3}), kT);
    ameoto::Canopy other(ameoto::CanopyGeometry{6, 0.5, 50}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    std::vector<double> forces(6);
    other.apply_force({1, 3}, 1.0);
    other.step(forces.data());
    double out = 1.0;
    ff.process(other, &out);
    CHECK(out == 0.0);
}
