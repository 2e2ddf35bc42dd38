// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/scene/drop_size_distribution: Marshall-Palmer, Joss et al., gamma (and Zhang's mu-Lambda),
// the water each delivers, and the impact flux they imply.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene/drop_size_distribution.hpp"
#include "engine/scene/terminal_speed.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"
#include "tests/engine/scene/scene_test_support.hpp"

using ameoto::test::NamedDsd;
using ameoto::test::v_of_mm;
using namespace ameoto::test::common;

namespace {

// Composite Simpson, written here independently of impact_flux.
double simpson(const std::function<double(double)>& f, double a, double b, int intervals) {
    if (intervals % 2) ++intervals;
    const double h = (b - a) / intervals;
    double sum = f(a) + f(b);
    for (int i = 1; i < intervals; ++i) sum += f(a + i * h) * ((i % 2) ? 4.0 : 2.0);
    return sum * h / 3.0;
}

}  // namespace

TEST_CASE("drop_size_distribution: Marshall-Palmer slope and density") {
    const ameoto::MarshallPalmer mp;
    for (double r : {0.1, 1.0, 5.0, 10.0, 25.0, 50.0, 100.0, 400.0}) {
        CAPTURE(r);
        // physics.md s.2: Lambda = 4.1 R^-0.21 mm^-1 (rounding only, 1e-12).
        CHECK(mp.lambda_per_mm(r) == ameoto::test::relative(4.1 * std::pow(r, -0.21)).epsilon(1e-12));
        // physics.md s.2: N(D) = 8000 exp(-Lambda D) m^-3 mm^-1.
        CHECK(mp.number_density(0.0, r) == doctest::Approx(8000.0).epsilon(1e-12));
        CHECK(mp.number_density(2.0, r) == ameoto::test::relative(8000.0 * std::exp(-2.0 * 4.1 * std::pow(r, -0.21))).epsilon(1e-12));
    }
    // Heavier rain has a shallower slope (more big drops).
    CHECK(mp.lambda_per_mm(50.0) < mp.lambda_per_mm(1.0));
    // Joss drizzle variant from physics.md s.2 through the parameters.
    const ameoto::MarshallPalmer drizzle{30000.0, 5.7, -0.21};
    CHECK(drizzle.lambda_per_mm(10.0) == ameoto::test::relative(5.7 * std::pow(10.0, -0.21)).epsilon(1e-12));
    CHECK(drizzle.number_density(0.0, 10.0) == doctest::Approx(30000.0));
}

TEST_CASE("drop_size_distribution: impact flux matches the physics.md table") {
    const ameoto::MarshallPalmer mp;
    const double rates[6] = {1, 5, 10, 25, 50, 100};
    // physics.md s.2, flux table (drops m^-2 s^-1), columns D >= 0.5 mm, D >= 1 mm, all D.
    const double ge_half[6] = {754, 2106, 3115, 5035, 7068, 9745};
    const double ge_one[6] = {152, 727, 1280, 2501, 3946, 6002};
    const double all_d[6] = {1756, 3541, 4742, 6910, 9123, 11972};
    for (int i = 0; i < 6; ++i) {
        CAPTURE(rates[i]);
        // physics.md s.2 / s.5 item 7: flux table, 5 %. Upper limit 8 mm: N(8 mm) is negligible.
        CHECK(ameoto::impact_flux(mp, rates[i], 0.5, 8.0) == ameoto::test::relative(ge_half[i]).epsilon(0.05));
        CHECK(ameoto::impact_flux(mp, rates[i], 1.0, 8.0) == ameoto::test::relative(ge_one[i]).epsilon(0.05));
        // The all-D column exercises the Stokes extension below 0.078 mm; same 5 %.
        CHECK(ameoto::impact_flux(mp, rates[i], 0.0, 8.0) == ameoto::test::relative(all_d[i]).epsilon(0.05));
    }
    // Degenerate inputs give no drops.
    CHECK(ameoto::impact_flux(mp, 0.0, 0.5, 6.0) == 0.0);
    CHECK(ameoto::impact_flux(mp, 10.0, 6.0, 0.5) == 0.0);
}

TEST_CASE("drop_size_distribution: impact_flux agrees with an independent Simpson integral") {
    const ameoto::MarshallPalmer mp;
    for (double r : {0.05, 1.0, 20.0, 300.0}) {
        for (auto [lo, hi] : {std::pair{0.5, 6.0}, std::pair{1.0, 3.0}, std::pair{0.1, 8.0}}) {
            const double mine = simpson([&](double d) { return mp.number_density(d, r) * v_of_mm(d); }, lo, hi, 40000);
            CAPTURE(r);
            CAPTURE(lo);
            // Both are Simpson on a piecewise-linear-times-exponential integrand; the engine's 0.005 mm
            // steps leave quadrature error far below 0.1 % (drop_size_distribution.cpp comment).
            CHECK(ameoto::impact_flux(mp, r, lo, hi) == ameoto::test::relative(mine).epsilon(1e-3));
        }
    }
}

TEST_CASE("drop_size_distribution: plain Marshall-Palmer over-delivers water (1.18 R at 1, 1.05 R at 100 mm/h)") {
    const ameoto::MarshallPalmer mp;
    // physics.md s.2: water volume 6 pi 1e-4 integral D^3 v N dD (mm/h) = 1.18 R at R = 1 and 1.05 R at
    // R = 100 (computed there). Integrated over all D (to 20 mm: the tail beyond is < 1e-6 of it).
    auto water_mm_per_h = [&](double r) {
        return 6.0 * kPi * 1e-4 *
               simpson([&](double d) { return d * d * d * v_of_mm(d) * mp.number_density(d, r); }, 0.0, 20.0, 40000);
    };
    // physics.md s.2 (computed values), 3 %.
    CHECK(water_mm_per_h(1.0) == ameoto::test::relative(1.18 * 1.0).epsilon(0.03));
    CHECK(water_mm_per_h(100.0) == doctest::Approx(1.05 * 100.0).epsilon(0.03));
}

namespace {

// The five distributions the rain scenes offer (drop_size_distribution.hpp), with their names.
std::vector<NamedDsd> distributions_offered() {
    using D = ameoto::DropSizeDistribution;
    return {{"Marshall-Palmer", D::marshall_palmer()},
            {"Joss drizzle", D::joss_drizzle()},
            {"Joss thunderstorm", D::joss_thunderstorm()},
            {"gamma mu=2 Lambda=4", D::gamma(2.0, 4.0)},
            {"gamma Zhang Lambda=3", D::gamma_zhang(3.0)}};
}

double water_independent(const ameoto::DropSizeDistribution& dsd, double r) {
    // N0 once (water-matched N0 is itself an integral); the shape and the quadrature are this file's own.
    const double n0 = dsd.n0_at(r);
    return 6.0 * kPi * 1e-4 * n0 * simpson([&](double d) { return d * d * d * v_of_mm(d) * dsd.shape(d, r); }, 1e-9, 20.0, 40000);
}

}  // namespace

TEST_CASE("drop_size_distribution: Joss et al. 1968 presets and the gamma family's parameters") {
    using D = ameoto::DropSizeDistribution;
    for (double r : {0.5, 1.0, 10.0, 50.0}) {
        CAPTURE(r);
        // physics.md s.2: drizzle N0 = 30000, Lambda = 5.7 R^-0.21; thunderstorm N0 = 1400, Lambda = 3.0 R^-0.21
        // (rounding only, 1e-12).
        CHECK(D::joss_drizzle().lambda_per_mm(r) == ameoto::test::relative(5.7 * std::pow(r, -0.21)).epsilon(1e-12));
        CHECK(D::joss_drizzle().number_density(0.0, r) == doctest::Approx(30000.0).epsilon(1e-12));
        CHECK(D::joss_thunderstorm().lambda_per_mm(r) == ameoto::test::relative(3.0 * std::pow(r, -0.21)).epsilon(1e-12));
        CHECK(D::joss_thunderstorm().number_density(1.0, r) ==
              doctest::Approx(1400.0 * std::exp(-3.0 * std::pow(r, -0.21))).epsilon(1e-12));
        // A fixed-Lambda gamma keeps its shape at every rate.
        CHECK(D::gamma(2.0, 4.0).lambda_per_mm(r) == 4.0);
        CHECK(D::gamma(2.0, 4.0).mu_at(r) == 2.0);
        CHECK(D::gamma(2.0, 4.0).shape(1.5, r) == ameoto::test::relative(1.5 * 1.5 * std::exp(-6.0)).epsilon(1e-12));
    }
    // Zhang et al. 2001 (physics.md s.2): mu = -0.016 Lambda^2 + 1.213 Lambda - 1.957 (rounding only).
    for (double l : {1.0, 3.0, 10.0, 20.0}) CHECK(ameoto::zhang_mu(l) == ameoto::test::relative(-0.016 * l * l + 1.213 * l - 1.957).epsilon(1e-12));
    CHECK(D::gamma_zhang(3.0).mu_at(7.0) == ameoto::test::relative(1.538).epsilon(1e-12));
    // With a rate-dependent slope, mu follows Lambda.
    D z = D::gamma_zhang(4.1);
    z.lambda_exponent = -0.21;
    CHECK(z.mu_at(50.0) == ameoto::test::relative(ameoto::zhang_mu(4.1 * std::pow(50.0, -0.21))).epsilon(1e-12));
    // The old name is the same type, and its default is Marshall-Palmer.
    const ameoto::MarshallPalmer old{};
    CHECK(old.n0_per_m3_mm == 8000.0);
    CHECK(old.n0_mode == ameoto::N0Mode::published);
}

TEST_CASE("drop_size_distribution: delivered water per distribution (N0 published vs water-matched)") {
    for (const auto& [name, dsd] : distributions_offered()) {
        INFO(std::string(name));
        std::string line = std::string(name) + ": water delivered / R at R = 1, 10, 50, 100 mm/h:";
        for (double r : {1.0, 10.0, 50.0, 100.0}) {
            const double w = dsd.water_mm_per_h(r);
            // The engine's water integral against the independent Simpson here (40000 intervals): 1e-4.
            CHECK(w == ameoto::test::relative(water_independent(dsd, r)).epsilon(1e-4));
            if (dsd.n0_mode == ameoto::N0Mode::water_matched) {
                // drop_size_distribution.hpp: water-matched N0 delivers exactly R (quadrature only, 1e-6).
                CHECK(w == ameoto::test::relative(r).epsilon(1e-6));
            }
            char buf[32];
            std::snprintf(buf, sizeof buf, " %.3f", w / r);
            line += buf;
        }
        MESSAGE(line);
    }
    // A preset switched to water_matched delivers R too; its shape (and so its sampled sizes) is unchanged.
    auto mp = ameoto::DropSizeDistribution::marshall_palmer();
    mp.n0_mode = ameoto::N0Mode::water_matched;
    CHECK(mp.water_mm_per_h(1.0) == ameoto::test::relative(1.0).epsilon(1e-6));
    // physics.md s.2: plain MP delivers 1.18 R at 1 mm/h, so the matched N0 is 8000 / 1.18 (3 %).
    CHECK(mp.n0_at(1.0) == doctest::Approx(8000.0 / 1.18).epsilon(0.03));
    CHECK(mp.shape(2.0, 1.0) == ameoto::DropSizeDistribution::marshall_palmer().shape(2.0, 1.0));
}

TEST_CASE("drop_size_distribution: impact_flux of every distribution agrees with an independent integral") {
    for (const auto& [name, dsd] : distributions_offered()) {
        for (double r : {1.0, 10.0, 50.0}) {
            INFO(std::string(name));
            CAPTURE(r);
            const double n0 = dsd.n0_at(r);
            const double mine =
                n0 * simpson([&](double d) { return dsd.shape(d, r) * v_of_mm(d); }, 0.5, 6.0, 40000);
            // Same 1e-3 as the Marshall-Palmer case above.
            CHECK(ameoto::impact_flux(dsd, r, 0.5, 6.0) == ameoto::test::relative(mine).epsilon(1e-3));
        }
    }
    // A gamma with mu < 0 has N(0) infinite but a finite flux from D = 0 (v ~ D^2 there).
    const auto g = ameoto::DropSizeDistribution::gamma(-0.5, 2.0);
    const double all = ameoto::impact_flux(g, 10.0, 0.0, 6.0);
    CHECK(std::isfinite(all));
    CHECK(all > ameoto::impact_flux(g, 10.0, 0.5, 6.0));
}
