// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/radiation: the seed's single-mass output and the Rayleigh far field.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <limits>
#include <random>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/models/radiation.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using ameoto::Vec3;

namespace {

constexpr double kRho = ameoto::constants::air_density;

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

// The far field as it was first written, kept as the reference for the scatter (radiation.hpp,
// "Delays"): one delay line per element holding its past a_i, read per (point, element) at floor(D) and
// floor(D) + 1 and summed per group. Same weights, same sum, added in another order.
class DelayLineRadiator {
public:
    DelayLineRadiator(const std::vector<ameoto::RadiatingElement>& elements, const std::vector<Vec3>& points, int groups,
                      double time_step_s, const ameoto::AirMedium& air = ameoto::AirMedium{})
        : elements_(elements), points_(points), groups_(groups) {
        const std::size_t n = elements_.size();
        taps_.resize(points_.size() * n);
        int longest = 0;
        for (std::size_t p = 0; p < points_.size(); ++p) {
            for (std::size_t e = 0; e < n; ++e) {
                const ameoto::RadiatingElement& el = elements_[e];
                const Vec3 d = points_[p] - el.position;
                const double floor = 0.5 * std::sqrt(el.area / kPi);
                const double r = std::max(ameoto::norm(d), floor);
                const double side = ameoto::dot(d, el.normal) < 0.0 ? -1.0 : 1.0;
                const double g = side * air.density * el.area / (2.0 * kPi * r);
                const double delay = r / (air.speed_of_sound * time_step_s);
                const double whole = std::floor(delay), frac = delay - whole;
                Tap& t = taps_[p * n + e];
                t.offset = static_cast<int>(whole);
                t.w0 = (1.0 - frac) * g;
                t.w1 = frac * g;
                t.distance = r;
                t.delay = delay;
                longest = std::max(longest, t.offset + 1);
            }
        }
        int length = 1;
        while (length < longest + 1) length *= 2;
        mask_ = length - 1;
        history_.assign(n * static_cast<std::size_t>(length), 0.0);
    }
    void process(const double* accelerations, double* out) {
        const std::size_t n = elements_.size(), length = static_cast<std::size_t>(mask_) + 1;
        write_ = (write_ + 1) & mask_;
        for (std::size_t e = 0; e < n; ++e)
            history_[e * length + static_cast<std::size_t>(write_)] = std::isfinite(accelerations[e]) ? accelerations[e] : 0.0;
        for (std::size_t o = 0; o < points_.size() * static_cast<std::size_t>(groups_); ++o) out[o] = 0.0;
        for (std::size_t p = 0; p < points_.size(); ++p) {
            double* row = out + p * static_cast<std::size_t>(groups_);
            for (std::size_t e = 0; e < n; ++e) {
                const Tap& t = taps_[p * n + e];
                const double* ring = history_.data() + e * length;
                const double now = ring[static_cast<std::size_t>((write_ - t.offset) & mask_)];
                const double before = ring[static_cast<std::size_t>((write_ - t.offset - 1) & mask_)];
                row[elements_[e].group] += t.w0 * now + t.w1 * before;
            }
        }
    }
    void reset() {
        std::fill(history_.begin(), history_.end(), 0.0);
        write_ = 0;
    }
    double distance(int p, int e) const { return tap(p, e).distance; }
    double delay_samples(int p, int e) const { return tap(p, e).delay; }
    double gain(int p, int e) const { return tap(p, e).w0 + tap(p, e).w1; }
    int history_length() const { return mask_ + 1; }

private:
    struct Tap {
        int offset = 0;
        double w0 = 0.0, w1 = 0.0, distance = 0.0, delay = 0.0;
    };
    const Tap& tap(int p, int e) const { return taps_[static_cast<std::size_t>(p) * elements_.size() + static_cast<std::size_t>(e)]; }
    std::vector<ameoto::RadiatingElement> elements_;
    std::vector<Vec3> points_;
    int groups_ = 1;
    std::vector<Tap> taps_;
    std::vector<double> history_;
    int mask_ = 0, write_ = 0;
};

std::vector<ameoto::RadiatingElement> canopy_elements(const ameoto::Canopy& canopy) {
    std::vector<ameoto::RadiatingElement> elements;
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i)
            elements.push_back({canopy.rest_position(k, i), canopy.normal(k, i), canopy.node_area(), k});
    return elements;
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
                CHECK(out[n][0] == ameoto::test::relative(expected).epsilon(1e-14));
                CHECK(out[n][1] == ameoto::test::relative(-expected).epsilon(1e-14));   // the other face: -a
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
        CHECK(out[24][0] == ameoto::test::relative(0.7 * g).epsilon(1e-12));
        CHECK(out[25][0] == ameoto::test::relative(0.3 * g).epsilon(1e-12));
        double total = 0.0;
        for (const auto& o : out) total += o[0];
        CHECK(total == ameoto::test::relative(g).epsilon(1e-14));   // the interpolation keeps the area
    }
    SUBCASE("a listening point on the element: the disc's own integral rho0 a a_eq") {
        ameoto::RayleighRadiator rad({{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, area, 0}}, {{0.0, 0.0, 0.0}}, 1, kT);
        CHECK(rad.gain(0, 0) == ameoto::test::relative(kRho * std::sqrt(area / kPi)).epsilon(1e-14));
    }
}

TEST_CASE("radiation: the scatter equals per-element delay lines to rounding (random elements, resets, NaN)") {
    // Elements from 4 mm of a point (floor(D) = 0: the tap adds into the sample being read) to 0.88 m
    // (floor(D) + 1 = 125 of the ring's run of 128), 3 groups, 3 points, inputs that are sometimes NaN
    // or infinite, a reset halfway, and far more samples than the ring holds (its window moves back to
    // the front every run).
    std::mt19937 rng(20240611);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const std::vector<Vec3> points{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.01}, {0.0, 0.0, -0.02}};
    std::vector<ameoto::RadiatingElement> elements;
    for (int e = 0; e < 60; ++e) {
        const Vec3 dir{unit(rng), unit(rng), unit(rng)};
        const Vec3 n = (1.0 / ameoto::norm(dir)) * dir;
        const Vec3 at = e == 0 ? 0.004 * n : e == 1 ? Vec3{0.0, 0.0, -0.88} : 0.2 * (1.0 + unit(rng)) * n;
        elements.push_back({at, n, e == 0 ? 1e-4 : 1e-3 * (1.5 + unit(rng)), (e * 7) % 3});
    }
    ameoto::RayleighRadiator rad(elements, points, 3, kT);
    DelayLineRadiator ref(elements, points, 3, kT);
    CHECK(rad.history_length() == ref.history_length());
    REQUIRE(rad.history_length() == 128);
    CHECK(std::floor(rad.delay_samples(0, 0)) == 0.0);
    CHECK(std::floor(rad.delay_samples(1, 1)) == 124.0);
    for (int p = 0; p < 3; ++p) {
        for (int e = 0; e < 60; ++e) {   // the queries are the same numbers, not merely close
            CHECK(rad.distance(p, e) == ref.distance(p, e));
            CHECK(rad.delay_samples(p, e) == ref.delay_samples(p, e));
            CHECK(rad.gain(p, e) == ref.gain(p, e));
        }
    }
    std::vector<double> a(60), out(9), expected(9);
    double peak = 0.0, worst = 0.0;
    for (int n = 0; n < 3000; ++n) {
        for (double& x : a) x = unit(rng) * (unit(rng) > 0.6 ? 1e3 : 1.0);
        if (n % 97 == 5) a[static_cast<std::size_t>(n % 60)] = std::numeric_limits<double>::quiet_NaN();
        if (n % 89 == 7) a[static_cast<std::size_t>((n + 11) % 60)] = -std::numeric_limits<double>::infinity();
        if (n == 1500) {
            rad.reset();
            ref.reset();
        }
        rad.process(a.data(), out.data());
        ref.process(a.data(), expected.data());
        for (std::size_t o = 0; o < 9; ++o) {
            REQUIRE(std::isfinite(out[o]));
            peak = std::max(peak, std::abs(expected[o]));
            worst = std::max(worst, std::abs(out[o] - expected[o]));
        }
    }
    REQUIRE(peak > 0.0);
    CHECK(worst <= 1e-12 * peak);
    MESSAGE("scatter vs delay lines, random elements: largest difference " << worst / peak << " of the peak");
}

TEST_CASE("radiation: the canopy's far field equals per-element delay lines to rounding") {
    // The real canopies (flat and curved), struck on several panels, heard by mono, two ears and a ring:
    // FarFieldRadiation (scatter, velocities read from the panels' networks) against the delay lines
    // fed with the accelerations computed here from Canopy::normal_velocity, mixed per channel.
    for (const double curvature : {std::numeric_limits<double>::infinity(), 1.5}) {
        for (int layout_kind = 0; layout_kind < 3; ++layout_kind) {
            CAPTURE(curvature);
            CAPTURE(layout_kind);
            ameoto::Canopy canopy(ameoto::CanopyGeometry{8, 0.5, 50, curvature}, ameoto::MembraneMaterial::nylon_canopy(), kT);
            const Vec3 head{0.0, 0.0, -0.3};
            std::vector<std::vector<double>> gains(3, std::vector<double>(8));
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 8; ++k) gains[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)] = 0.2 + 0.1 * ((c + k) % 5);
            const ameoto::ListenerLayout layout = layout_kind == 0   ? ameoto::ListenerLayout::mono(head)
                                                  : layout_kind == 1 ? ameoto::ListenerLayout::ears(head, 0.4)
                                                                     : ameoto::ListenerLayout::panned(head, gains);
            ameoto::FarFieldRadiation ff(canopy, layout, kT);
            DelayLineRadiator ref(canopy_elements(canopy), layout.points, 8, kT);
            const int nodes = 8 * canopy.nodes_per_panel(), channels = layout.channels();
            std::vector<double> forces(8), v_prev(static_cast<std::size_t>(nodes), 0.0), a(static_cast<std::size_t>(nodes));
            std::vector<double> sums(layout.points.size() * 8), out(static_cast<std::size_t>(channels));
            double peak = 0.0, worst = 0.0;
            for (int n = 0; n < 2400; ++n) {
                if (n % 300 < 4) canopy.apply_force({(n / 300) % 8, (7 * (n / 300)) % 50}, -0.2);
                canopy.step(forces.data());
                ff.process(canopy, out.data());
                for (int e = 0; e < nodes; ++e) {
                    const double v = canopy.normal_velocity(e / canopy.nodes_per_panel(), e % canopy.nodes_per_panel());
                    a[static_cast<std::size_t>(e)] = (v - v_prev[static_cast<std::size_t>(e)]) * (1.0 / kT);
                    v_prev[static_cast<std::size_t>(e)] = v;
                }
                ref.process(a.data(), sums.data());
                for (int c = 0; c < channels; ++c) {
                    double expected = 0.0;
                    for (int k = 0; k < 8; ++k) {
                        const double g = layout.panel_gain.empty() ? 1.0 : layout.panel_gain[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)];
                        expected += g * sums[static_cast<std::size_t>(layout.channel_point[static_cast<std::size_t>(c)] * 8 + k)];
                    }
                    peak = std::max(peak, std::abs(expected));
                    worst = std::max(worst, std::abs(out[static_cast<std::size_t>(c)] - expected));
                }
            }
            REQUIRE(peak > 0.0);
            CHECK(worst <= 1e-12 * peak);
            MESSAGE("scatter vs delay lines, canopy Rc " << curvature << ", layout " << layout_kind
                                                         << ": largest difference " << worst / peak << " of the peak");
        }
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
    CHECK(layout.points[0].y == ameoto::test::relative(0.09).epsilon(1e-15));    // left ear: +y when facing +x
    CHECK(layout.points[1].y == ameoto::test::relative(-0.09).epsilon(1e-15));
    ameoto::FarFieldRadiation ff(canopy, layout, kT);
    // Panel 2 is at azimuth 90 degrees: on the listener's left.
    const auto& rad = ff.radiator();
    const int node = 20, e = 2 * canopy.nodes_per_panel() + node;
    const Vec3 x = canopy.rest_position(2, node);
    CHECK(rad.distance(0, e) == ameoto::test::relative(ameoto::norm(x - layout.points[0])).epsilon(1e-14));
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
    CHECK(ameoto::MassPickup(canopy, 0, interior).full_scale_m() == ameoto::test::relative(10.0 / (6.0 * 1000.0 / std::sqrt(3.0))).epsilon(1e-12));
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

TEST_CASE("radiation: inputs read through an index (the canopy's lanes) give the same bits as the caller's order") {
    // Three elements in two groups, read from a 5-long input at 3, 0 and 4 (1 and 2 unread): fed the
    // same accelerations, the remapped radiator and the plain one agree to the bit, through process()
    // and through inputs() + process_inputs(); the unread entries change nothing, NaN counts as 0.
    std::vector<ameoto::RadiatingElement> elements = {{{0.1, 0.0, 0.0}, {0.0, 0.0, 1.0}, 2e-3, 0},
                                                      {{0.0, 0.2, 0.0}, {0.0, 0.0, 1.0}, 3e-3, 1},
                                                      {{-0.1, 0.1, 0.05}, {0.0, 0.0, 1.0}, 1e-3, 1}};
    const std::vector<Vec3> points = {{0.0, 0.0, -0.3}, {0.05, 0.0, -0.25}};
    ameoto::RayleighRadiator plain(elements, points, 2, kT), mapped(elements, points, 2, kT), in_place(elements, points, 2, kT);
    mapped.read_inputs_at({3, 0, 4}, 5);
    in_place.read_inputs_at({3, 0, 4}, 5);
    REQUIRE(in_place.input_count() == 5);
    std::vector<double> o_plain(4), o_mapped(4), o_in_place(4);
    long differing = 0;
    for (int n = 0; n < 200; ++n) {
        const double a0 = std::sin(0.3 * n), a1 = n % 17 == 0 ? std::numeric_limits<double>::quiet_NaN() : std::cos(0.11 * n), a2 = 0.5 - (n % 7) * 0.1;
        const double caller[3] = {a0, a1, a2};
        const double laid_out[5] = {a1, 1e9 * n, -3.0, a0, a2};   // entries 1 and 2 are read by no element
        plain.process(caller, o_plain.data());
        mapped.process(laid_out, o_mapped.data());
        double* in = in_place.inputs();
        for (int i = 0; i < 5; ++i) in[i] = std::isfinite(laid_out[i]) ? laid_out[i] : 0.0;
        in_place.process_inputs(o_in_place.data());
        for (std::size_t o = 0; o < 4; ++o) {
            differing += std::memcmp(&o_plain[o], &o_mapped[o], sizeof(double)) != 0;
            differing += std::memcmp(&o_plain[o], &o_in_place[o], sizeof(double)) != 0;
        }
    }
    CHECK(differing == 0);
    CHECK(std::abs(o_plain[0]) + std::abs(o_plain[1]) > 0.0);
    ameoto::RayleighRadiator bad(elements, points, 2, kT);
    CHECK_THROWS_AS(bad.read_inputs_at({0, 1}, 5), std::invalid_argument);      // one index per element
    CHECK_THROWS_AS(bad.read_inputs_at({0, 1, 5}, 5), std::invalid_argument);   // out of range
    CHECK_THROWS_AS(bad.read_inputs_at({0, -1, 2}, 5), std::invalid_argument);
}
