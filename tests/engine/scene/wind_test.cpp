// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/scene/wind: the ramps, the gust process's statistics, the drops' lag, tilt and impact
// velocity closed forms, the rate a surface sees, and the real-time audit.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "engine/core/physical_constants.hpp"
#include "engine/core/random.hpp"
#include "engine/scene/drop_size_distribution.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "engine/scene/terminal_speed.hpp"
#include "engine/scene/wind.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

namespace {

double deg(double d) { return d * kPi / 180.0; }

// Along and across the mean direction.
double along(const ameoto::Vec3& v, double dir) { return v.x * std::cos(dir) + v.y * std::sin(dir); }
double across(const ameoto::Vec3& v, double dir) { return -v.x * std::sin(dir) + v.y * std::cos(dir); }

}  // namespace

TEST_CASE("wind: speed and direction ramp linearly in 1 s, direction along the shorter arc") {
    ameoto::Wind wind;   // ramp_s = 1, steady
    ameoto::Random rng(1);
    wind.set_now(0.0, deg(170.0));
    wind.set_speed(10.0);
    wind.set_direction(deg(-170.0));   // 20 degrees counter-clockwise through 180, not 340 clockwise
    double min_abs_dir = kPi;
    for (int n = 1; n <= 48000; ++n) {
        wind.advance(kDt, rng);
        min_abs_dir = std::min(min_abs_dir, std::abs(wind.direction()));
        if (n == 12000) {
            // wind.hpp: linear ramps over ramp_s (rounding of 12000 sums: 1e-9).
            CHECK(wind.mean_speed() == doctest::Approx(2.5).epsilon(1e-9));
            CHECK(wind.direction() == doctest::Approx(deg(175.0)).epsilon(1e-9));
        }
        if (n == 24000) {
            CHECK(wind.mean_speed() == doctest::Approx(5.0).epsilon(1e-9));
            CHECK(std::abs(wind.direction()) == doctest::Approx(kPi).epsilon(1e-9));
        }
        if (n == 47000) CHECK(wind.mean_speed() < 10.0);
    }
    CHECK(min_abs_dir >= deg(170.0) - 1e-9);   // never took the long way round
    CHECK(wind.mean_speed() == doctest::Approx(10.0).epsilon(1e-9));
    CHECK(wind.direction() == doctest::Approx(deg(-170.0)).epsilon(1e-9));
    wind.advance(kDt, rng);
    CHECK(wind.mean_speed() == 10.0);   // reached exactly, no overshoot
    CHECK(wind.direction() == doctest::Approx(deg(-170.0)).epsilon(1e-15));
    // Steady wind (I = 0): the air is the mean wind exactly.
    CHECK(wind.velocity().x == doctest::Approx(10.0 * std::cos(deg(-170.0))).epsilon(1e-12));
    CHECK(wind.velocity().y == doctest::Approx(10.0 * std::sin(deg(-170.0))).epsilon(1e-12));
    CHECK(wind.velocity().z == 0.0);
    // Down takes ramp_s too; the speed is clamped to 0..60 m/s.
    wind.set_speed(4.0);
    for (int n = 0; n < 24000; ++n) wind.advance(kDt, rng);
    CHECK(wind.mean_speed() == doctest::Approx(7.0).epsilon(1e-9));
    wind.set_speed(1000.0);
    CHECK(wind.target_speed() == 60.0);
    wind.set_speed(-1.0);
    CHECK(wind.target_speed() == 0.0);
    CHECK_THROWS(ameoto::Wind(ameoto::Wind::Config{.length_scale_m = 0.0}));
    CHECK_THROWS(ameoto::Wind(ameoto::Wind::Config{.turbulence_intensity = -0.1}));
}

TEST_CASE("wind: gusts have the OU mean, standard deviation and correlation time of their parameters") {
    // I = 0.27 (EN 1991-1-4 at 2 m, open country), U = 5 m/s, L_u = 11.3 m: sigma_u = 1.35 m/s,
    // T_u = 2.26 s; lateral sigma_v = 1.08 m/s, T_v = 0.753 s (wind.hpp, IEC 61400-1 Kaimal ratios).
    ameoto::Wind::Config cfg;
    cfg.turbulence_intensity = ameoto::Wind::turbulence_intensity_at(2.0, 0.05);
    ameoto::Wind wind(cfg);
    const double u = 5.0, dir = deg(40.0);
    wind.set_now(u, dir);
    ameoto::Random rng(2024);
    const double sigma_u = cfg.turbulence_intensity * u, sigma_v = 0.8 * sigma_u;
    const double t_u = wind.gust_time_s(), t_v = t_u / 3.0;
    CHECK(t_u == doctest::Approx(11.3 / 5.0).epsilon(1e-12));

    const double dt = 0.01, total = 20000.0;   // the exact OU transition makes the statistics independent of dt
    const int steps = static_cast<int>(total / dt), lag_u = static_cast<int>(std::lround(t_u / dt));
    std::vector<double> xs(static_cast<std::size_t>(steps));
    double su = 0, su2 = 0, sv = 0, sv2 = 0;
    for (int n = 0; n < steps; ++n) {
        wind.advance(dt, rng);
        const double gu = along(wind.velocity(), dir) - u, gv = across(wind.velocity(), dir);
        xs[static_cast<std::size_t>(n)] = gu;
        su += gu, su2 += gu * gu, sv += gv, sv2 += gv * gv;
    }
    const double mu_u = su / steps, sd_u = std::sqrt(su2 / steps - mu_u * mu_u);
    const double mu_v = sv / steps, sd_v = std::sqrt(sv2 / steps - mu_v * mu_v);
    double c = 0.0;
    for (int n = 0; n + lag_u < steps; ++n) c += (xs[static_cast<std::size_t>(n)] - mu_u) * (xs[static_cast<std::size_t>(n + lag_u)] - mu_u);
    const double rho = c / (steps - lag_u) / (sd_u * sd_u);
    MESSAGE("gusts over 20000 s: u' mean " << mu_u << " sd " << sd_u << " (" << sigma_u << "), v' mean " << mu_v << " sd "
                                           << sd_v << " (" << sigma_v << "), autocorrelation at T_u " << rho << " (1/e = 0.368)");
    // Standard error of an OU mean over a record of length L: sigma sqrt(2 T / L) (0.015 sigma_u here); 4 SE.
    CHECK(std::abs(mu_u) < 4.0 * sigma_u * std::sqrt(2.0 * t_u / total));
    CHECK(std::abs(mu_v) < 4.0 * sigma_v * std::sqrt(2.0 * t_v / total));
    // Relative standard error of the sample sd is about sqrt(T / L) (1.1 % for u', 0.6 % for v'); 4 %, 3 %.
    CHECK(sd_u == ameoto::test::relative(sigma_u).epsilon(0.04));
    CHECK(sd_v == ameoto::test::relative(sigma_v).epsilon(0.03));
    // OU autocorrelation exp(-lag / T) = 1/e at T_u; its standard error is about sqrt(T / L) here too: +/- 0.04.
    CHECK(std::abs(rho - std::exp(-1.0)) < 0.04);
    // The same process stepped at 4.8 kHz for 2000 s: same sd (10 %, a shorter record).
    ameoto::Wind fine(cfg);
    fine.set_now(u, dir);
    double f2 = 0.0;
    const int fine_steps = 2000 * 4800;
    for (int n = 0; n < fine_steps; ++n) {
        fine.advance(1.0 / 4800.0, rng);
        f2 += fine.longitudinal_gust() * fine.longitudinal_gust();
    }
    CHECK(std::sqrt(f2 / fine_steps) == ameoto::test::relative(sigma_u).epsilon(0.10));
    // EN 1991-1-4: I = 1 / ln(z / z0) = 0.271 at 2 m, z0 = 0.05 m; gust factor sqrt(1 + 7 I) (rounding only).
    CHECK(cfg.turbulence_intensity == ameoto::test::relative(1.0 / std::log(40.0)).epsilon(1e-12));
    CHECK(wind.gust_factor() == doctest::Approx(std::sqrt(1.0 + 7.0 / std::log(40.0))).epsilon(1e-12));
    CHECK(ameoto::Wind::turbulence_intensity_at(2.0, 1.0) == ameoto::test::relative(1.0 / std::log(10.0)).epsilon(1e-12));   // z_min 10 m
}

TEST_CASE("wind: a steady wind draws no random numbers; the same seed gives the same gusts") {
    ameoto::Wind calm;
    calm.set_now(5.0, 0.0);
    ameoto::Random a(9), b(9);
    for (int n = 0; n < 1000; ++n) calm.advance(kDt, a);
    CHECK(a.next_u64() == b.next_u64());
    ameoto::Wind g1(ameoto::Wind::Config{.turbulence_intensity = 0.3}), g2(ameoto::Wind::Config{.turbulence_intensity = 0.3});
    g1.set_now(8.0, 1.0);
    g2.set_now(8.0, 1.0);
    ameoto::Random r1(5), r2(5);
    for (int n = 0; n < 10000; ++n) {
        g1.advance(kDt, r1);
        g2.advance(kDt, r2);
    }
    CHECK(g1.velocity().x == g2.velocity().x);
    CHECK(g1.horizontal_velocity(2e-3).y == g2.horizontal_velocity(2e-3).y);
}

TEST_CASE("wind: drops follow the wind, lagging with tau = v_t / g (ramp response closed form)") {
    // A 0 -> 10 m/s ramp over Tr = 1 s through a first-order lag tau:
    //   y = k (t - tau (1 - exp(-t / tau)))            for t <= Tr, k = U / Tr,
    //   y = U - k tau exp(-t / tau) (exp(Tr / tau) - 1)  after.
    ameoto::Wind wind;
    ameoto::Random rng(3);
    const double u = 10.0, tr = 1.0, k = u / tr;
    wind.set_now(0.0, 0.0);
    wind.set_speed(u);
    const double diameters_mm[] = {0.05, 0.1, 0.3, 0.5, 0.8, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 5.8};
    double worst = 0.0;
    for (int n = 1; n <= 3 * 48000; ++n) {
        wind.advance(kDt, rng);
        if (n % 4800) continue;
        const double t = n * kDt;
        for (double d : diameters_mm) {
            const double tau = ameoto::terminal_speed(d * 1e-3) / ameoto::constants::gravity;
            const double y = t <= tr ? k * (t - tau * (1.0 - std::exp(-t / tau)))
                                     : u - k * tau * std::exp(-t / tau) * (std::exp(tr / tau) - 1.0);
            worst = std::max(worst, std::abs(wind.horizontal_velocity(d * 1e-3).x - y));
            CHECK(wind.horizontal_velocity(d * 1e-3).y == 0.0);
        }
    }
    MESSAGE("drop lag: worst deviation from the closed form over 0.05..5.8 mm: " << worst << " m/s of a 10 m/s ramp");
    // wind.hpp: 12 filters interpolated in ln tau, plus the staircase of a per-sample ramp: 1 % of U.
    CHECK(worst < 0.01 * u);
    // response_time_s is v_t / g: 0.41 s at 1 mm, 0.935 s at 5.8 mm (Gunn-Kinzer 4.03, 9.17 m/s).
    CHECK(ameoto::Wind::response_time_s(1e-3) == ameoto::test::relative(4.03 / 9.80665).epsilon(1e-12));
    // Small drops follow the wind fully: a 0.05 mm drop (tau 7 ms) lags a 10 m/s^2 ramp by k tau = 0.07 m/s
    // at most; in a steady wind every drop moves with it (after 33 s the largest's lag is e^-35 of k tau).
    for (int n = 0; n < 30 * 48000; ++n) wind.advance(kDt, rng);
    for (double d : diameters_mm) CHECK(wind.horizontal_velocity(d * 1e-3).x == doctest::Approx(u).epsilon(1e-9));
}

TEST_CASE("wind: tilt, impact velocity and surface rate factor closed forms in a steady wind") {
    ameoto::Wind wind;
    ameoto::Random rng(4);
    const double u = 6.0, dir = deg(30.0), c = std::cos(dir), s = std::sin(dir);
    wind.set_now(u, dir);
    for (int n = 0; n < 100; ++n) wind.advance(kDt, rng);
    const ameoto::Vec3 up{0, 0, 1}, windward{-c, -s, 0}, lee{c, s, 0};
    const double tilt_angle = deg(30.0);
    const ameoto::Vec3 panel{-std::sin(tilt_angle) * c, -std::sin(tilt_angle) * s, std::cos(tilt_angle)};   // faces the wind
    for (double d_mm : {0.5, 1.0, 2.0, 5.0}) {
        CAPTURE(d_mm);
        const double d = d_mm * 1e-3, vt = ameoto::terminal_speed(d);
        // All closed forms below hold to rounding (1e-12): drops move with the wind; fall speed v_t.
        CHECK(wind.tilt(d) == ameoto::test::relative(std::atan(u / vt)).epsilon(1e-12));
        const auto v = wind.drop_velocity(d);
        CHECK(v.x == doctest::Approx(u * c).epsilon(1e-12));
        CHECK(v.y == doctest::Approx(u * s).epsilon(1e-12));
        CHECK(v.z == doctest::Approx(-vt).epsilon(1e-12));

        auto h = wind.impact(d, up);   // horizontal: v_t into it, the wind along it
        CHECK(h.normal_speed == doctest::Approx(vt).epsilon(1e-12));
        CHECK(h.tangential.x == doctest::Approx(u * c).epsilon(1e-12));
        CHECK(std::abs(h.tangential.z) < 1e-12);
        CHECK(h.incidence_rad == ameoto::test::relative(std::atan(u / vt)).epsilon(1e-12));
        CHECK(wind.surface_rate_factor(d, up) == doctest::Approx(1.0).epsilon(1e-12));

        h = wind.impact(d, windward);   // a wall facing the wind: U into it, v_t down it
        CHECK(h.normal_speed == doctest::Approx(u).epsilon(1e-12));
        CHECK(h.tangential.z == doctest::Approx(-vt).epsilon(1e-12));
        CHECK(h.incidence_rad == ameoto::test::relative(std::atan(vt / u)).epsilon(1e-12));
        // Blocken & Carmeliet 2004 eq. 2: R_wdr / R_h = U / V_t.
        CHECK(wind.surface_rate_factor(d, windward) == ameoto::test::relative(u / vt).epsilon(1e-12));

        h = wind.impact(d, lee);   // the lee face: moving away from it, no drops
        CHECK(h.normal_speed == doctest::Approx(-u).epsilon(1e-12));
        CHECK(wind.surface_rate_factor(d, lee) == 0.0);

        h = wind.impact(d, panel);   // 30 degrees up-tilted panel facing the wind
        CHECK(h.normal_speed == doctest::Approx(vt * std::cos(tilt_angle) + u * std::sin(tilt_angle)).epsilon(1e-12));
        CHECK(wind.surface_rate_factor(d, panel) == doctest::Approx(std::cos(tilt_angle) + u / vt * std::sin(tilt_angle)).epsilon(1e-12));
        // The thinning bound holds.
        CHECK(wind.max_surface_rate_factor(panel, 0.5e-3) >= wind.surface_rate_factor(d, panel));
        CHECK(wind.max_surface_rate_factor(windward, 0.5e-3) >= wind.surface_rate_factor(d, windward));
    }
    // Calm: no tilt.
    ameoto::Wind calm;
    CHECK(calm.tilt(2e-3) == 0.0);
}

TEST_CASE("wind: gusts modulate the rate on a tilted surface, not on a horizontal one") {
    ameoto::Wind wind(ameoto::Wind::Config{.turbulence_intensity = 0.27});
    ameoto::Random rng(6);
    const double u = 5.0;
    wind.set_now(u, 0.0);
    const ameoto::Vec3 up{0, 0, 1}, wall{-1, 0, 0};
    const double d = 1e-3, vt = ameoto::terminal_speed(d);
    double sum = 0.0, sum2 = 0.0, worst_flat = 0.0;
    const int steps = 400000;   // 4000 s at 100 Hz
    for (int n = 0; n < steps; ++n) {
        wind.advance(0.01, rng);
        const double f = wind.surface_rate_factor(d, wall);
        sum += f, sum2 += f * f;
        worst_flat = std::max(worst_flat, std::abs(wind.surface_rate_factor(d, up) - 1.0));
    }
    // Horizontal: exactly 1 whatever the gusts (rounding only).
    CHECK(worst_flat < 1e-12);
    const double mean = sum / steps, sd = std::sqrt(sum2 / steps - mean * mean);
    MESSAGE("1 mm drops on a windward wall, U = 5 m/s, I = 0.27: rate factor mean " << mean << " (U/v_t = " << u / vt
                                                                                    << "), sd " << sd);
    // The drops' mean velocity is U, and u_drop < 0 is rare (a 3.7 sigma_u event, less after the lag), so
    // the mean factor is U / v_t; standard error ~ sd sqrt(2 T / L) = 3 %: 10 %.
    CHECK(mean == ameoto::test::relative(u / vt).epsilon(0.10));
    // It fluctuates: sd of u_drop / v_t is at most sigma_u / v_t = 0.33 (the lag lowers it); above 0.1.
    CHECK(sd > 0.1);
    CHECK(sd < 0.27 * u / vt);
}

TEST_CASE("wind: thinning a RainSpawner gives the wind-driven rain on a wall (Blocken & Carmeliet)") {
    // Wall of 1 m^2 facing a steady 5 m/s wind, Marshall-Palmer 5 mm/h, D in 0.5..6 mm: drops strike at
    // integral N(D) v(D) (U / v(D)) dD = U integral N dD = U N0 / Lambda (exp(-0.5 Lambda) - exp(-6 Lambda)).
    ameoto::Wind wind;
    wind.set_now(5.0, 0.0);
    const ameoto::Vec3 wall{-1, 0, 0};
    ameoto::RainSpawner rain(ameoto::RainSpawner::Config{});
    rain.set_rate_now(5.0);
    ameoto::Random rng(8);
    const double l = 4.1 * std::pow(5.0, -0.21);
    const double expected_rate = 5.0 * 8000.0 / l * (std::exp(-0.5 * l) - std::exp(-6.0 * l));
    const double seconds = 20.0;
    std::int64_t struck = 0;
    for (int n = 0; n < static_cast<int>(seconds * 48000); ++n) {
        wind.advance(kDt, rng);
        const double f_max = wind.max_surface_rate_factor(wall, rain.config().d_min_mm * 1e-3);
        const int k = rain.advance(kDt, rng, f_max);
        for (int i = 0; i < k; ++i) {
            const double d = rain.sample_diameter_m(rng);
            if (rng.uniform() * f_max < wind.surface_rate_factor(d, wall)) ++struck;
        }
    }
    const double expected = expected_rate * seconds;
    MESSAGE("wall facing 5 m/s at 5 mm/h: " << struck / seconds << " drops m^-2 s^-1, closed form " << expected_rate);
    // Thinning is exact: Poisson, 5 standard deviations.
    CHECK(std::abs(static_cast<double>(struck) - expected) < 5.0 * std::sqrt(expected));
}

TEST_CASE("wind: allocation-free per step and per query (real-time audit)") {
    ameoto::Wind wind(ameoto::Wind::Config{.turbulence_intensity = 0.27});
    ameoto::Random rng(10);
    wind.set_now(3.0, 0.5);
    double sink = 0.0;
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        wind.set_speed(8.0);
        wind.set_direction(-2.0);
        for (int n = 0; n < 4800; ++n) {
            wind.advance(kDt, rng);
            const double d = 0.5e-3 + 4e-3 * (n % 7) / 7.0;
            const auto hit = wind.impact(d, {0.3, 0.0, 0.95});
            sink += hit.normal_speed + wind.tilt(d) + wind.surface_rate_factor(d, {0, 0, 1}) +
                    wind.max_surface_rate_factor({-1, 0, 0}, 0.5e-3) + wind.drop_velocity(d).x;
        }
    }
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    CHECK(std::isfinite(sink));
}
