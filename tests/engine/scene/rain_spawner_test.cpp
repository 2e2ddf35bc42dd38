// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/scene/rain_spawner: Poisson arrivals at the impact flux, flux-weighted diameters,
// the rate ramp, and the same for every drop size distribution.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/scene/drop_size_distribution.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "engine/scene/terminal_speed.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"
#include "tests/engine/scene/scene_test_support.hpp"

using ameoto::test::NamedDsd;
using ameoto::test::v_of_mm;
using namespace ameoto::test::common;

namespace {

// CDF of the flux-weighted density N(D) v(D) truncated to [lo, hi], tabulated by the trapezoid rule on
// a fine grid (independent of the engine's sampler).
struct FluxCdf {
    double lo, hi, step;
    std::vector<double> cdf;
    FluxCdf(double lambda, double lo_mm, double hi_mm, int points) : lo(lo_mm), hi(hi_mm) {
        step = (hi - lo) / (points - 1);
        cdf.assign(static_cast<std::size_t>(points), 0.0);
        auto f = [&](double d) { return std::exp(-lambda * d) * v_of_mm(d); };
        for (int i = 1; i < points; ++i) {
            const double a = lo + (i - 1) * step, b = lo + i * step;
            cdf[static_cast<std::size_t>(i)] = cdf[static_cast<std::size_t>(i - 1)] + 0.5 * (f(a) + f(b)) * step;
        }
        const double total = cdf.back();
        for (auto& c : cdf) c /= total;
    }
    double operator()(double d) const {
        if (d <= lo) return 0.0;
        if (d >= hi) return 1.0;
        const double pos = (d - lo) / step;
        const auto i = std::min(static_cast<std::size_t>(pos), cdf.size() - 2);
        const double t = pos - static_cast<double>(i);
        return cdf[i] * (1.0 - t) + cdf[i + 1] * t;
    }
};

// Weighted maximum likelihood slope of an exponential truncated to [lo, hi]: solves
// mean_w(D - lo) = 1/L - W / (exp(L W) - 1), W = hi - lo, by bisection (the right side falls with L).
double truncated_exponential_mle(const std::vector<double>& d_mm, const std::vector<double>& w, double lo, double hi) {
    double sw = 0.0, swd = 0.0;
    for (std::size_t i = 0; i < d_mm.size(); ++i) {
        sw += w[i];
        swd += w[i] * (d_mm[i] - lo);
    }
    const double mean = swd / sw, width = hi - lo;
    auto g = [&](double l) { return 1.0 / l - width / std::expm1(l * width); };
    double a = 1e-3, b = 100.0;
    for (int it = 0; it < 200; ++it) {
        const double m = 0.5 * (a + b);
        (g(m) > mean ? a : b) = m;
    }
    return 0.5 * (a + b);
}

}  // namespace

TEST_CASE("rain_spawner: tabulated flux matches impact_flux within 0.2 % from 0.02 to 400 mm/h") {
    const ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
    const ameoto::MarshallPalmer mp;
    for (int i = 0; i < 40; ++i) {
        const double r = 0.02 * std::pow(400.0 / 0.02, i / 39.0);
        CAPTURE(r);
        // Brief / rain_spawner.cpp: log-log table interpolation, 0.2 %.
        CHECK(rain.flux_per_m2_s(r) == ameoto::test::relative(ameoto::impact_flux(mp, r, 0.5, 6.0)).epsilon(0.002));
    }
    CHECK(rain.flux_per_m2_s(0.0) == 0.0);
    CHECK(rain.flux_per_m2_s(-3.0) == 0.0);
    // Below the table (0.01 mm/h) the flux falls linearly to 0: positive and below the flux at 0.01.
    CHECK(rain.flux_per_m2_s(0.005) > 0.0);
    CHECK(rain.flux_per_m2_s(0.005) < rain.flux_per_m2_s(0.01));
}

TEST_CASE("rain_spawner: impact count over 200 s at 5 mm/h on 1 m^2") {
    ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
    rain.set_rate_now(5.0);
    ameoto::Random rng(20240501);
    const int steps = 200 * 48000;
    std::int64_t count = 0;
    for (int n = 0; n < steps; ++n) count += rain.advance(kDt, rng);
    const double per_m2_s = static_cast<double>(count) / 200.0;
    // physics.md s.2 table (D >= 0.5 mm at 5 mm/h) and s.5 item 7: 2106 within 5 %.
    CHECK(per_m2_s == doctest::Approx(2106.0).epsilon(0.05));
    // Poisson: the count is within 5 standard deviations (sqrt of the mean) of the spawner's own flux.
    const double expected = rain.flux_per_m2_s(5.0) * 200.0;
    CHECK(std::abs(static_cast<double>(count) - expected) < 5.0 * std::sqrt(expected));
}

TEST_CASE("rain_spawner: arrivals are Poisson (Fano factor 1, exponential gaps)") {
    SUBCASE("counts in 10 ms windows at 50 mm/h on 1 m^2 for 100 s") {
        ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
        rain.set_rate_now(50.0);
        ameoto::Random rng(7);
        const int window = 480, windows = 10000;   // 10 ms at 48 kHz, 100 s
        double sum = 0.0, sum2 = 0.0;
        for (int w = 0; w < windows; ++w) {
            int c = 0;
            for (int n = 0; n < window; ++n) c += rain.advance(kDt, rng);
            sum += c;
            sum2 += static_cast<double>(c) * c;
        }
        const double mean = sum / windows;
        const double var = (sum2 - sum * sum / windows) / (windows - 1);
        // Mean near 70.7 drops per window (physics.md table: 7068 m^-2 s^-1), 5 %.
        CHECK(mean == doctest::Approx(70.68).epsilon(0.05));
        // physics.md s.2: arrivals are Poisson, Fano factor 1; the estimator's standard error is
        // sqrt(2 / n) = 0.014 for 10^4 windows, so +/- 0.05 is 3.5 sigma.
        CHECK(var / mean == ameoto::test::relative(1.0).epsilon(0.05));
    }
    SUBCASE("gaps at a low rate: coefficient of variation 1 and P(gap > mean) = 1/e") {
        ameoto::RainSpawner::Config cfg;
        cfg.area_m2 = 0.01;   // ~21 drops/s at 5 mm/h: gaps ~2300 samples, so the 1-sample grid is negligible
        ameoto::RainSpawner rain(cfg);
        rain.set_rate_now(5.0);
        ameoto::Random rng(99);
        std::vector<double> gaps;
        std::int64_t last = -1;
        for (std::int64_t n = 0; gaps.size() < 10000; ++n) {
            const int a = rain.advance(kDt, rng);
            for (int k = 0; k < a; ++k) {
                if (last >= 0) gaps.push_back(static_cast<double>(n - last) * kDt);
                last = n;
            }
        }
        double s = 0.0, s2 = 0.0;
        for (double g : gaps) {
            s += g;
            s2 += g * g;
        }
        const double n = static_cast<double>(gaps.size());
        const double mean = s / n, sd = std::sqrt((s2 - s * s / n) / (n - 1));
        // Exponential gaps with mean 1/(flux * area): 5 standard errors (1/sqrt(n) = 1 %) -> 5 %.
        CHECK(mean == ameoto::test::relative(1.0 / (rain.flux_per_m2_s(5.0) * cfg.area_m2)).epsilon(0.05));
        // Exponential: CV = 1; its standard error is ~1/sqrt(n) = 1 %; 5 %.
        CHECK(sd / mean == ameoto::test::relative(1.0).epsilon(0.05));
        const double above = static_cast<double>(std::count_if(gaps.begin(), gaps.end(), [&](double g) { return g > mean; })) / n;
        // Binomial standard error sqrt(p(1-p)/n) = 0.0048; 5 sigma = 0.024.
        CHECK(std::abs(above - std::exp(-1.0)) < 0.024);
    }
}

TEST_CASE("rain_spawner: sampled diameters follow the flux-weighted Marshall-Palmer distribution") {
    const ameoto::MarshallPalmer mp;
    for (double r : {1.0, 10.0, 50.0}) {
        CAPTURE(r);
        ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
        rain.set_rate_now(r);
        ameoto::Random rng(1000 + static_cast<std::uint64_t>(r));
        const int n = 20000;
        std::vector<double> d(static_cast<std::size_t>(n));
        for (auto& x : d) x = rain.sample_diameter_m(rng) * 1e3;
        const double lo = 0.5, hi = 6.0;
        CHECK(*std::min_element(d.begin(), d.end()) >= lo);
        CHECK(*std::max_element(d.begin(), d.end()) <= hi);

        // Kolmogorov-Smirnov against N(D) v(D) on [0.5, 6] mm, CDF integrated here.
        const FluxCdf cdf(mp.lambda_per_mm(r), lo, hi, 22001);
        std::sort(d.begin(), d.end());
        double ks = 0.0;
        for (int i = 0; i < n; ++i) {
            const double f = cdf(d[static_cast<std::size_t>(i)]);
            ks = std::max({ks, f - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - f});
        }
        // physics.md s.5 item 6: KS p > 0.01, i.e. D_n below the 1 % critical value 1.63 / sqrt(n).
        CHECK(ks < 1.63 / std::sqrt(static_cast<double>(n)));

        // Weight each impact by 1/v(D) to recover N(D) itself, then fit the truncated exponential slope.
        std::vector<double> w(d.size());
        for (std::size_t i = 0; i < d.size(); ++i) w[i] = 1.0 / v_of_mm(d[i]);
        const double lambda = truncated_exponential_mle(d, w, lo, hi);
        // physics.md s.5 item 6: fitted Lambda within 3 % of 4.1 R^-0.21.
        CHECK(lambda == ameoto::test::relative(4.1 * std::pow(r, -0.21)).epsilon(0.03));
    }
}

TEST_CASE("rain_spawner: KS test detects a wrong distribution (the test can fail)") {
    // Samples drawn at 1 mm/h are compared with the 50 mm/h CDF: the statistic must exceed the
    // 1 % critical value, so the check above is not vacuous.
    const ameoto::MarshallPalmer mp;
    ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
    rain.set_rate_now(1.0);
    ameoto::Random rng(5);
    const int n = 20000;
    std::vector<double> d(static_cast<std::size_t>(n));
    for (auto& x : d) x = rain.sample_diameter_m(rng) * 1e3;
    std::sort(d.begin(), d.end());
    const FluxCdf cdf(mp.lambda_per_mm(50.0), 0.5, 6.0, 5501);
    double ks = 0.0;
    for (int i = 0; i < n; ++i) ks = std::max(ks, std::abs(cdf(d[static_cast<std::size_t>(i)]) - (i + 0.5) / n));
    CHECK(ks > 1.63 / std::sqrt(static_cast<double>(n)));
}

TEST_CASE("rain_spawner: rate ramp and clamping") {
    ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});   // ramp_s = 1 s
    ameoto::Random rng(1);
    CHECK(rain.rate() == 0.0);
    rain.set_rate(30.0);
    CHECK(rain.target_rate() == 30.0);
    CHECK(rain.rate() == 0.0);   // set_rate does not jump
    for (int n = 0; n < 24000; ++n) rain.advance(kDt, rng);   // 0.5 s
    CHECK(rain.rate() > 0.0);
    CHECK(rain.rate() < 30.0);
    // rain_spawner.hpp: linear ramp over ramp_s, so half way at 0.5 s (rounding of 24000 sums: 1e-9).
    CHECK(rain.rate() == doctest::Approx(15.0).epsilon(1e-9));
    for (int n = 0; n < 23000; ++n) rain.advance(kDt, rng);   // 0.979 s: still ramping
    CHECK(rain.rate() < 30.0);
    for (int n = 0; n < 1000; ++n) rain.advance(kDt, rng);    // 1.0 s
    CHECK(rain.rate() == doctest::Approx(30.0).epsilon(1e-9));
    rain.advance(kDt, rng);
    CHECK(rain.rate() == 30.0);   // reached, and never overshoots
    for (int n = 0; n < 1000; ++n) rain.advance(kDt, rng);
    CHECK(rain.rate() == 30.0);

    // Ramping down takes ramp_s as well.
    rain.set_rate(10.0);
    for (int n = 0; n < 24000; ++n) rain.advance(kDt, rng);
    CHECK(rain.rate() == doctest::Approx(20.0).epsilon(1e-9));

    // Clamping to [0, 500] mm/h.
    rain.set_rate(1000.0);
    CHECK(rain.target_rate() == 500.0);
    rain.set_rate(-5.0);
    CHECK(rain.target_rate() == 0.0);
    rain.set_rate_now(1e9);
    CHECK(rain.rate() == 500.0);
    rain.set_rate_now(-1.0);
    CHECK(rain.rate() == 0.0);
    // At rate 0 nothing arrives.
    int arrivals = 0;
    for (int n = 0; n < 48000; ++n) arrivals += rain.advance(kDt, rng);
    CHECK(arrivals == 0);
}

TEST_CASE("rain_spawner: arrivals follow the ramp (count during a 0 -> 30 mm/h ramp)") {
    // Time rescaling is exact while the rate ramps: the expected count over the 1 s ramp on 1 m^2 is the
    // integral of the flux along the ramp, here by the trapezoid rule on the spawner's own flux table.
    const int trials = 20;
    double total = 0.0, expected = 0.0;
    for (int t = 0; t < trials; ++t) {
        ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
        ameoto::Random rng(300 + static_cast<std::uint64_t>(t));
        rain.set_rate(30.0);
        for (int n = 0; n < 48000; ++n) total += rain.advance(kDt, rng);
        if (t == 0)
            for (int n = 0; n < 48000; ++n) expected += rain.flux_per_m2_s(30.0 * (n + 1) / 48000.0) * kDt;
    }
    expected *= trials;
    // Poisson, 5 standard deviations.
    CHECK(std::abs(total - expected) < 5.0 * std::sqrt(expected));
}

TEST_CASE("rain_spawner: rejects bad configurations") {
    ameoto::RainSpawner::Config cfg;
    cfg.area_m2 = 0.0;
    CHECK_THROWS(ameoto::RainSpawner{cfg});
    cfg = {};
    cfg.d_min_mm = 3.0;
    cfg.d_max_mm = 2.0;
    CHECK_THROWS(ameoto::RainSpawner{cfg});
}

// ---- Every drop size distribution (drop_size_distribution.hpp) through the spawner ----

namespace {

std::vector<NamedDsd> distributions_through_spawner() {
    using D = ameoto::DropSizeDistribution;
    D zhang_mp_slope = D::gamma_zhang(4.1);   // Zhang's mu with Marshall-Palmer's slope: mu from 2.75 to 0.17
    zhang_mp_slope.lambda_exponent = -0.21;
    return {{"Marshall-Palmer", D::marshall_palmer()},
            {"Joss drizzle", D::joss_drizzle()},
            {"Joss thunderstorm", D::joss_thunderstorm()},
            {"gamma mu=2 Lambda=4", D::gamma(2.0, 4.0)},
            {"gamma mu=-0.5 Lambda=2", D::gamma(-0.5, 2.0)},
            {"gamma Zhang Lambda=3", D::gamma_zhang(3.0)},
            {"gamma Zhang Lambda=4.1R^-0.21", zhang_mp_slope}};
}

// Flux-weighted CDF of D^mu exp(-lambda D) v(D) on [lo, hi] (trapezoid on a fine grid; this file's own).
struct GammaFluxCdf {
    double lo, hi, step;
    std::vector<double> cdf;
    GammaFluxCdf(double mu, double lambda, double lo_mm, double hi_mm, int points) : lo(lo_mm), hi(hi_mm) {
        step = (hi - lo) / (points - 1);
        cdf.assign(static_cast<std::size_t>(points), 0.0);
        auto f = [&](double d) { return std::pow(d, mu) * std::exp(-lambda * d) * v_of_mm(d); };
        for (int i = 1; i < points; ++i) {
            const double a = lo + (i - 1) * step, b = lo + i * step;
            cdf[static_cast<std::size_t>(i)] = cdf[static_cast<std::size_t>(i - 1)] + 0.5 * (f(a) + f(b)) * step;
        }
        const double total = cdf.back();
        for (auto& c : cdf) c /= total;
    }
    double operator()(double d) const {
        if (d <= lo) return 0.0;
        if (d >= hi) return 1.0;
        const double pos = (d - lo) / step;
        const auto i = std::min(static_cast<std::size_t>(pos), cdf.size() - 2);
        const double t = pos - static_cast<double>(i);
        return cdf[i] * (1.0 - t) + cdf[i + 1] * t;
    }
};

// Asymptotic Kolmogorov p-value with Stephens' small-sample correction (Press et al., Numerical Recipes,
// 3rd ed., section 14.3.3): p = Q(lambda), lambda = (sqrt(n) + 0.12 + 0.11 / sqrt(n)) D.
double ks_p_value(double d, int n) {
    const double sn = std::sqrt(static_cast<double>(n));
    const double l = (sn + 0.12 + 0.11 / sn) * d;
    if (l < 0.2) return 1.0;
    double p = 0.0, sign = 1.0;
    for (int k = 1; k <= 100; ++k) {
        p += sign * 2.0 * std::exp(-2.0 * k * k * l * l);
        sign = -sign;
    }
    return std::clamp(p, 0.0, 1.0);
}

// Weighted maximum likelihood of Lambda for D^mu(Lambda) exp(-Lambda D) truncated to [lo, hi], with mu
// fixed or tied to Lambda (Zhang). Weights 1/v(D) turn the impacts back into N(D). A log grid over
// 0.3..40 mm^-1, then golden section around the best point.
double fit_lambda(const std::vector<double>& d, const ameoto::DropSizeDistribution& dsd, double lo, double hi) {
    double sw = 0.0, swd = 0.0, swl = 0.0;
    for (double x : d) {
        const double w = 1.0 / v_of_mm(x);
        sw += w;
        swd += w * x;
        swl += w * std::log(x);
    }
    auto loglik = [&](double l) {
        const double mu = dsd.mu_from_lambda ? ameoto::zhang_mu(l) : dsd.mu;
        const int m = 2000;
        const double h = (hi - lo) / m;
        double z = 0.0;
        for (int i = 0; i <= m; ++i) {
            const double x = lo + i * h;
            z += ((i == 0 || i == m) ? 1.0 : ((i % 2) ? 4.0 : 2.0)) * std::pow(x, mu) * std::exp(-l * x);
        }
        z *= h / 3.0;
        return mu * swl - l * swd - sw * std::log(z);
    };
    double best = 0.3, best_ll = -1e300;
    for (int i = 0; i <= 200; ++i) {
        const double l = 0.3 * std::pow(40.0 / 0.3, i / 200.0);
        const double ll = loglik(l);
        if (ll > best_ll) best_ll = ll, best = l;
    }
    double a = best / 1.03, b = best * 1.03;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 80; ++it) {
        const double c = b - g * (b - a), e = a + g * (b - a);
        (loglik(c) > loglik(e) ? b : a) = (loglik(c) > loglik(e) ? e : c);
    }
    return 0.5 * (a + b);
}

}  // namespace

TEST_CASE("rain_spawner: every DSD's sampled diameters follow its flux-weighted distribution") {
    const double lo = 0.5, hi = 6.0;
    const int n = 20000;
    for (const auto& [name, dsd] : distributions_through_spawner()) {
        INFO(std::string(name));
        ameoto::RainSpawner::Config cfg;
        cfg.dsd = dsd;
        ameoto::RainSpawner rain(cfg);
        std::string line = std::string(name) + ":";
        for (double r : {1.0, 10.0, 50.0}) {
            CAPTURE(r);
            rain.set_rate_now(r);
            ameoto::Random rng(4000 + static_cast<std::uint64_t>(r));
            std::vector<double> d(static_cast<std::size_t>(n));
            for (auto& x : d) x = rain.sample_diameter_m(rng) * 1e3;
            CHECK(*std::min_element(d.begin(), d.end()) >= lo);
            CHECK(*std::max_element(d.begin(), d.end()) <= hi);
            std::sort(d.begin(), d.end());
            const GammaFluxCdf cdf(dsd.mu_at(r), dsd.lambda_per_mm(r), lo, hi, 22001);
            double ks = 0.0;
            for (int i = 0; i < n; ++i) {
                const double f = cdf(d[static_cast<std::size_t>(i)]);
                ks = std::max({ks, f - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - f});
            }
            const double p = ks_p_value(ks, n);
            // physics.md s.5 item 6 and the brief: KS p > 0.01 against N(D) v(D) on [0.5, 6] mm.
            CHECK(p > 0.01);
            const double lambda = fit_lambda(d, dsd, lo, hi);
            const double expected = dsd.lambda_per_mm(r);
            // physics.md s.5 item 6: fitted Lambda within 3 % of the distribution's Lambda(R).
            CHECK(lambda == ameoto::test::relative(expected).epsilon(0.03));
            char buf[96];
            std::snprintf(buf, sizeof buf, "  R=%g: Lambda fit %.4f vs %.4f (%+.2f %%), KS D=%.4f p=%.3f", r, lambda,
                          expected, 100.0 * (lambda / expected - 1.0), ks, p);
            line += buf;
        }
        MESSAGE(line);
    }
}

TEST_CASE("rain_spawner: every DSD's counts follow its own flux table; arrivals are Poisson") {
    for (const auto& [name, dsd] : distributions_through_spawner()) {
        INFO(std::string(name));
        ameoto::RainSpawner::Config cfg;
        cfg.dsd = dsd;
        ameoto::RainSpawner rain(cfg);
        // The table against the integral: 0.2 % (as for Marshall-Palmer above).
        for (double r : {0.05, 1.0, 5.0, 50.0, 300.0}) {
            CAPTURE(r);
            CHECK(rain.flux_per_m2_s(r) == ameoto::test::relative(ameoto::impact_flux(dsd, r, 0.5, 6.0)).epsilon(0.002));
        }
        rain.set_rate_now(10.0);
        ameoto::Random rng(77);
        const int window = 480, windows = 10000;   // 10 ms at 48 kHz, 100 s
        double sum = 0.0, sum2 = 0.0;
        for (int w = 0; w < windows; ++w) {
            int c = 0;
            for (int s = 0; s < window; ++s) c += rain.advance(kDt, rng);
            sum += c;
            sum2 += static_cast<double>(c) * c;
        }
        const double mean = sum / windows, var = (sum2 - sum * sum / windows) / (windows - 1);
        const double expected = rain.flux_per_m2_s(10.0) * 100.0;
        // Poisson count over 100 s: within 5 standard deviations of the table's flux.
        CHECK(std::abs(sum - expected) < 5.0 * std::sqrt(expected));
        // Fano factor 1 +/- 0.05 (3.5 standard errors for 10^4 windows, as above).
        CHECK(var / mean == ameoto::test::relative(1.0).epsilon(0.05));
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s: flux D>=0.5 mm at 1/5/10/50 mm/h = %.0f/%.0f/%.0f/%.0f m^-2 s^-1; counted %.0f m^-2 s^-1 at 10; Fano %.3f",
                      name, rain.flux_per_m2_s(1.0), rain.flux_per_m2_s(5.0), rain.flux_per_m2_s(10.0),
                      rain.flux_per_m2_s(50.0), sum / 100.0, var / mean);
        MESSAGE(buf);
    }
}

TEST_CASE("rain_spawner: the flux scale multiplies the arrival rate exactly (time rescaling)") {
    // advance(dt, rng, s): arrivals at s times the flux; s = 1 is the plain advance, sample for sample.
    ameoto::RainSpawner a(ameoto::RainSpawner::Config{}), b(ameoto::RainSpawner::Config{});
    a.set_rate_now(20.0);
    b.set_rate_now(20.0);
    ameoto::Random ra(3), rb(3);
    for (int n = 0; n < 48000; ++n) REQUIRE(a.advance(kDt, ra) == b.advance(kDt, rb, 1.0));
    // A varying scale (a square wave 0.5 / 2.5, mean 1.5) over 50 s: count within 5 sigma of its integral.
    ameoto::RainSpawner c(ameoto::RainSpawner::Config{});
    c.set_rate_now(5.0);
    ameoto::Random rc(11);
    double count = 0.0, expected = 0.0;
    for (int n = 0; n < 50 * 48000; ++n) {
        const double s = ((n / 4800) % 2) ? 2.5 : 0.5;
        count += c.advance(kDt, rc, s);
        expected += c.flux_per_m2_s(5.0) * s * kDt;
    }
    CHECK(std::abs(count - expected) < 5.0 * std::sqrt(expected));
    CHECK(c.advance(kDt, rc, 0.0) == 0);
}

TEST_CASE("rain_spawner: rejects distributions without a valid shape over 0.01..500 mm/h") {
    ameoto::RainSpawner::Config cfg;
    cfg.dsd = ameoto::DropSizeDistribution::gamma(-1.2, 2.0);   // mu <= -1: not integrable
    CHECK_THROWS_AS(ameoto::RainSpawner{cfg}, std::invalid_argument);
    cfg.dsd = ameoto::DropSizeDistribution::gamma(1.0, -2.0);   // Lambda <= 0
    CHECK_THROWS_AS(ameoto::RainSpawner{cfg}, std::invalid_argument);
    cfg.dsd = ameoto::DropSizeDistribution::gamma_zhang(0.5);   // Zhang mu(0.5) = -1.35
    CHECK_THROWS_AS(ameoto::RainSpawner{cfg}, std::invalid_argument);
}

TEST_CASE("rain_spawner: allocation-free per sample with every DSD (real-time audit)") {
    for (const auto& [name, dsd] : distributions_through_spawner()) {
        INFO(std::string(name));
        ameoto::RainSpawner::Config cfg;
        cfg.dsd = dsd;
        ameoto::RainSpawner rain(cfg);
        ameoto::Random rng(1);
        rain.set_rate_now(5.0);
        double sink = 0.0;
        ameoto::test::RtAudit audit;
        {
            ameoto::test::RtAudit::Scope scope;
            rain.set_rate(40.0);   // a ramp, so the shape is recomputed per sample
            for (int n = 0; n < 4800; ++n) {
                const int k = rain.advance(kDt, rng, 1.2);
                for (int i = 0; i < k; ++i) sink += rain.sample_diameter_m(rng);
            }
        }
        CHECK(audit.entries() > 0);
        CHECK_MESSAGE(audit.violations() == 0, audit.first());
        CHECK(sink > 0.0);
    }
}
