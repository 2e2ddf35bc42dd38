// Tests for engine/models/canopy: the umbrella's panels, where a point lands, and the runtime guard.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/canopy.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kT = 1.0 / 48000.0;

const ameoto::Canopy& default_canopy() {
    static const ameoto::Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    return canopy;
}

}  // namespace

TEST_CASE("canopy: plan area is N R^2 sin(2 pi / N) / 2") {
    for (int n : {3, 6, 8, 12}) {
        for (double r : {0.3, 0.5, 0.7}) {
            CAPTURE(n);
            CAPTURE(r);
            const ameoto::Canopy c(ameoto::CanopyGeometry{n, r, 30}, ameoto::MembraneMaterial::nylon_canopy(), kT);
            // canopy.hpp: plan area (rounding only).
            CHECK(c.area() == doctest::Approx(n * r * r * std::sin(2.0 * kPi / n) / 2.0).epsilon(1e-12));
            CHECK(c.panel_count() == n);
        }
    }
    // canopy.hpp: 0.707 m^2 for 8 panels of 0.5 m.
    CHECK(default_canopy().area() == doctest::Approx(0.7071).epsilon(1e-3));
}

TEST_CASE("canopy: default panels have about 50 masses and are stable") {
    const auto& c = default_canopy();
    REQUIRE(c.panel_count() == 8);
    for (int k = 0; k < c.panel_count(); ++k) {
        const int masses = c.panel(k).network.mass_count();
        // Seed (physics.md s.1): umbrella panel of about 50 masses; brief: 40..60.
        CHECK(masses >= 40);
        CHECK(masses <= 60);
        CHECK(c.panel(k).network.stability().margin() < 0.9);
    }
    // Hem free, ribs fixed: some nodes anchored, and the hem row is not.
    const auto& lat = c.panel(0).lattice;
    int anchored = 0;
    for (int a : lat.anchor_links) anchored += a > 0;
    CHECK(anchored > 0);
    CHECK(anchored < static_cast<int>(lat.nodes.size()));
}

TEST_CASE("canopy: locate finds the panel under a point") {
    const auto& c = default_canopy();
    for (int k = 0; k < c.panel_count(); ++k) {
        CAPTURE(k);
        const auto p = c.panel_centroid(k);
        const auto hit = c.locate(p.x, p.y);
        CHECK(hit.panel == k);
        CHECK(hit.node >= 0);
        CHECK(hit.node < c.panel(k).network.mass_count());
        // The centroid lies along the panel's azimuth at 2/3 of its height from the shaft.
        CHECK(std::atan2(p.y, p.x) == doctest::Approx(std::remainder(c.panel_azimuth(k), 2.0 * kPi)).epsilon(1e-12));
        CHECK(std::hypot(p.x, p.y) == doctest::Approx(2.0 / 3.0 * 0.5 * std::cos(kPi / 8)).epsilon(1e-12));
    }
    // Outside the radius at any azimuth: no panel.
    for (int i = 0; i < 360; ++i) {
        const double a = 2.0 * kPi * i / 360.0;
        CHECK(c.locate(0.501 * std::cos(a), 0.501 * std::sin(a)).panel == -1);
        CHECK(c.locate(2.0 * std::cos(a), 2.0 * std::sin(a)).panel == -1);
    }
    // Between the hem chord and the circle, on a panel's centre line: not on the (flat) canopy.
    CHECK(c.locate(0.48, 0.0).panel == -1);
    CHECK(c.locate(0.45, 0.0).panel == 0);
}

TEST_CASE("canopy: locate returns the node nearest the point, in the panel's frame") {
    // Rotating a point by one sector maps it onto the same node of the next panel (identical panels).
    const auto& c = default_canopy();
    ameoto::Random rng(8);
    for (int t = 0; t < 200; ++t) {
        const auto p = c.sample_point(rng);
        const auto hit = c.locate(p.x, p.y);
        REQUIRE(hit.panel >= 0);
        const double s = 2.0 * kPi / c.panel_count();
        const auto moved = c.locate(p.x * std::cos(s) - p.y * std::sin(s), p.x * std::sin(s) + p.y * std::cos(s));
        CHECK(moved.panel == (hit.panel + 1) % c.panel_count());
        CHECK(moved.node == hit.node);
    }
}

TEST_CASE("canopy: sample_point is uniform over the canopy") {
    const auto& c = default_canopy();
    ameoto::Random rng(11);
    const int n = 10000;
    std::vector<int> per_panel(static_cast<std::size_t>(c.panel_count()), 0);
    int off = 0, inner = 0;
    for (int i = 0; i < n; ++i) {
        const auto p = c.sample_point(rng);
        const auto hit = c.locate(p.x, p.y);
        if (hit.panel < 0) {
            ++off;
            continue;
        }
        ++per_panel[static_cast<std::size_t>(hit.panel)];
        // Uniform over a triangle from the shaft: P(distance < half the apothem) = 1/4.
        const double along = std::hypot(p.x, p.y) * std::cos(std::remainder(std::atan2(p.y, p.x), 2.0 * kPi / 8));
        inner += along < 0.5 * 0.5 * std::cos(kPi / 8);
    }
    CHECK(off == 0);   // every sample lands on the canopy
    const double mean = static_cast<double>(n) / c.panel_count();
    double chi2 = 0.0;
    for (int k : per_panel) {
        // Brief: each panel within 10 % of the mean (the binomial sd is 2.6 % of it, so ~4 sigma).
        CHECK(static_cast<double>(k) == doctest::Approx(mean).epsilon(0.10));
        chi2 += (k - mean) * (k - mean) / mean;
    }
    // Chi-square with 7 degrees of freedom: the 0.1 % critical value is 24.3.
    CHECK(chi2 < 24.3);
    // Binomial sd sqrt(n p (1-p)) = 43 around 2500; 5 sigma.
    CHECK(std::abs(inner - 0.25 * n) < 5.0 * std::sqrt(n * 0.25 * 0.75));
}

TEST_CASE("canopy: forces move the hit panel only, and the runtime guard resets a non-finite panel") {
    ameoto::Canopy c(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    std::vector<double> forces(static_cast<std::size_t>(c.panel_count()));
    const auto p = c.panel_centroid(3);
    const auto hit = c.locate(p.x, p.y);
    c.apply_force(hit, 0.5);
    c.step(forces.data());
    for (int k = 0; k < c.panel_count(); ++k) {
        CAPTURE(k);
        if (k == 3) CHECK(forces[static_cast<std::size_t>(k)] == doctest::Approx(0.5).epsilon(1e-12));   // first step: the external force
        else CHECK(forces[static_cast<std::size_t>(k)] == 0.0);
    }
    c.apply_force({}, 1.0);   // panel -1: ignored
    c.step(forces.data());
    CHECK(c.reset_unstable() == 0);

    // A non-finite force makes panel 3 non-finite; the guard resets exactly that panel.
    c.apply_force(hit, std::numeric_limits<double>::infinity());
    c.step(forces.data());
    c.step(forces.data());
    CHECK_FALSE(c.panel(3).network.finite());
    CHECK(c.panel(2).network.finite());
    CHECK(c.reset_unstable() == 1);
    CHECK(c.panel(3).network.finite());
    CHECK(c.reset_unstable() == 0);
    c.step(forces.data());
    for (double f : forces) CHECK(std::isfinite(f));
}

TEST_CASE("canopy: rejects bad geometry") {
    const auto mat = ameoto::MembraneMaterial::nylon_canopy();
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{2, 0.5, 50}, mat, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{65, 0.5, 50}, mat, kT), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::Canopy(ameoto::CanopyGeometry{8, 0.0, 50}, mat, kT), std::invalid_argument);
}
