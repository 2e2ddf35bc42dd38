// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/water_surface.hpp: entrainment by drop size, the impact's level, light rain's
// spectrum (physics.md section 5, check 10), determinism, capacity and the real-time audit.
#include "tests/support/sanitizer_bounds.hpp"
#include "engine/models/water_surface.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include "engine/core/fft.hpp"
#include "engine/core/random.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "engine/scene/terminal_speed.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

namespace {

using ameoto::Entrainment;
using ameoto::Random;
using ameoto::fft_in_place;
using ameoto::SplashClass;
using ameoto::WaterSurface;
using ameoto::WaterSurfaceConfig;

double minnaert_hz(double a) { return std::sqrt(3.0 * 1.4 * 101325.0 / 998.0) / (2.0 * kPi * a); }

// Welch average power spectrum: Hann windows of `size`, half overlapping. Bin k is k fs / size.
std::vector<double> welch(const std::vector<double>& x, std::size_t size) {
    std::vector<double> power(size / 2 + 1, 0.0), window(size);
    for (std::size_t i = 0; i < size; ++i) window[i] = 0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(size));
    std::vector<std::complex<double>> buffer(size);
    int segments = 0;
    for (std::size_t start = 0; start + size <= x.size(); start += size / 2, ++segments) {
        for (std::size_t i = 0; i < size; ++i) buffer[i] = x[start + i] * window[i];
        fft_in_place(buffer);
        for (std::size_t k = 0; k < power.size(); ++k) power[k] += std::norm(buffer[k]);
    }
    for (auto& p : power) p /= segments;
    return power;
}

struct RainRender {
    std::vector<double> samples;
    ameoto::WaterSurfaceStats stats;
};

// Rain from the project's rain model (RainSpawner: Poisson arrivals at Marshall-Palmer's impact flux,
// flux-weighted diameters; Gunn-Kinzer terminal speeds) striking one water surface.
RainRender rain_on_water(double rate_mm_per_h, double area_m2, double seconds, double fs, std::uint64_t seed,
                         int block = 1) {
    ameoto::RainSpawner rain(ameoto::RainSpawner::Config{.area_m2 = area_m2});
    rain.set_rate_now(rate_mm_per_h);
    WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = fs});
    Random rng(seed);
    RainRender r;
    const auto frames = static_cast<std::size_t>(seconds * fs);
    r.samples.assign(frames, 0.0);
    const double dt = 1.0 / fs;
    for (std::size_t n = 0; n < frames; n += static_cast<std::size_t>(block)) {
        const int count = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(block), frames - n));
        // Drops arriving during this block land at its start (block = 1: at their sample).
        for (int k = 0; k < count; ++k) {
            const int arrivals = rain.advance(dt, rng);
            for (int i = 0; i < arrivals; ++i) {
                const double d = rain.sample_diameter_m(rng);
                water.strike(d, ameoto::terminal_speed(d), rng);
            }
        }
        water.process(r.samples.data() + n, count);
    }
    r.stats = water.stats();
    return r;
}

}  // namespace

TEST_CASE("water_surface: entrainment by drop size follows the documented classes and laws") {
    // Binomial tolerance: 5 standard deviations of the fraction over N draws.
    constexpr int N = 20000;
    struct Case {
        double d_mm;
        SplashClass splash;
        double p;
    };
    const Case cases[] = {{0.5, SplashClass::tiny, 0.0},      {0.79, SplashClass::tiny, 0.0},
                          {0.8, SplashClass::small, 0.95},    {0.95, SplashClass::small, 0.95},
                          {1.1, SplashClass::small, 0.95},    {1.5, SplashClass::medium, 0.05},
                          {2.2, SplashClass::medium, 0.05},   {2.5, SplashClass::large, 0.2 + 0.3 * 0.3 / 1.8},
                          {3.1, SplashClass::large, 0.35},    {4.0, SplashClass::large, 0.5},
                          {5.5, SplashClass::large, 0.5}};
    Random rng(11);
    for (const Case& c : cases) {
        CAPTURE(c.d_mm);
        const double d = c.d_mm * 1e-3;
        CHECK(ameoto::splash_class(d) == c.splash);
        CHECK(ameoto::entrainment_probability(d) == doctest::Approx(c.p).epsilon(1e-12));
        int bubbles = 0;
        double ln_sum = 0.0, a_min = 1.0, a_max = 0.0;
        for (int i = 0; i < N; ++i) {
            const Entrainment e = ameoto::draw_entrainment(d, rng);
            CHECK(e.splash == c.splash);
            if (!e.bubble) continue;
            ++bubbles;
            ln_sum += std::log(e.radius_m);
            a_min = std::min(a_min, e.radius_m);
            a_max = std::max(a_max, e.radius_m);
        }
        const double fraction = static_cast<double>(bubbles) / N;
        const double sigma = std::sqrt(std::max(c.p * (1.0 - c.p), 1e-12) / N);
        CHECK(std::abs(fraction - c.p) <= 5.0 * sigma + 1e-12);
        if (bubbles == 0) continue;
        const double ln_mean = ln_sum / bubbles;
        if (c.splash == SplashClass::small) {
            // Log-linear from 0.24 mm at 0.8 mm to 0.14 mm at 1.1 mm, scatter e^(+-0.05): every pitch in
            // 13-25 kHz (physics.md section 4).
            const double s = (d - 0.8e-3) / 0.3e-3;
            const double ln_centre = (1.0 - s) * std::log(0.24e-3) + s * std::log(0.14e-3);
            CHECK(ln_mean == doctest::Approx(ln_centre).epsilon(1e-3));   // scatter mean 0, sd 0.029 / sqrt(N)
            CHECK(a_min >= std::exp(ln_centre - 0.05));
            CHECK(a_max <= std::exp(ln_centre + 0.05));
            CHECK(minnaert_hz(a_max) >= 13e3);
            CHECK(minnaert_hz(a_min) <= 25e3);
        } else {
            // Log-uniform in [0.1 mm, D / 4]: the mean of ln a is the middle (sd of the mean
            // (hi - lo) / sqrt(12 N); 5 of them), and the extremes come close to both ends.
            const double lo = std::log(0.1e-3), hi = std::log(d / 4.0);
            CHECK(a_min >= 0.1e-3);
            CHECK(a_max <= d / 4.0 * (1.0 + 1e-12));
            CHECK(std::abs(ln_mean - 0.5 * (lo + hi)) < 5.0 * (hi - lo) / std::sqrt(12.0 * bubbles));
            CHECK(std::log(a_min) - lo < 0.05 * (hi - lo));
            CHECK(hi - std::log(a_max) < 0.05 * (hi - lo));
            if (c.splash == SplashClass::large) CHECK(minnaert_hz(a_max) < 6.1e3);   // lower pitch than rain's 13-25 kHz
        }
    }
    // The light-rain bubble: about 0.22 mm at the lower end of the band (physics.md section 4).
    Random r2(3);
    double ln_sum = 0.0;
    int n = 0;
    for (int i = 0; i < N; ++i) {
        const Entrainment e = ameoto::draw_entrainment(0.85e-3, r2);
        if (e.bubble) {
            ln_sum += std::log(e.radius_m);
            ++n;
        }
    }
    CHECK(std::exp(ln_sum / n) == ameoto::test::relative(0.22e-3).epsilon(0.03));
    // Bad diameters: nothing, and still two draws.
    Random a(5), b(5);
    CHECK_FALSE(ameoto::draw_entrainment(NAN, a).bubble);
    CHECK_FALSE(ameoto::draw_entrainment(-1.0, a).bubble);
    b.uniform();
    b.uniform();
    b.uniform();
    b.uniform();
    CHECK(a.next_u64() == b.next_u64());
}

TEST_CASE("water_surface: strike() counts by class and starts the bubbles it draws") {
    WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = 96000.0});
    Random rng(7);
    int drawn = 0;
    for (int i = 0; i < 400; ++i) {
        const double d = (0.5 + 0.01 * (i % 500)) * 1e-3;
        const Entrainment e = water.strike(d, ameoto::terminal_speed(d), rng);
        drawn += e.bubble;
        double x[64];
        water.process(x, 64);
    }
    const auto& s = water.stats();
    CHECK(s.strikes == 400);
    CHECK(s.by_class[0] + s.by_class[1] + s.by_class[2] + s.by_class[3] == 400);
    CHECK(s.by_class[0] == 30);   // 0.50 .. 0.79 mm: i % 500 / 100 mm steps
    CHECK(s.by_class[1] == 31);   // 0.80 .. 1.10 mm
    CHECK(s.bubbles_entrained == static_cast<std::uint64_t>(drawn));
    CHECK(s.bubbles_started + s.bubbles_dropped + s.bubbles_above_band == s.bubbles_entrained);
    CHECK(s.bubbles_dropped == 0);
    CHECK(s.bubbles_above_band == 0);   // at 96 kHz every bubble of rain is below 43 kHz
    CHECK(s.rejected == 0);
    // Refused strikes: counted, nothing started, the random stream advances by two draws as always.
    Random a(9), b(9);
    CHECK_FALSE(water.strike(1e-3, 0.0, a).bubble);
    CHECK_FALSE(water.strike(1e-3, -4.0, a).bubble);
    CHECK_FALSE(water.strike(0.0, 4.0, a).bubble);
    CHECK_FALSE(water.strike(1e-3, NAN, a).bubble);
    CHECK(water.stats().rejected == 4);
    for (int i = 0; i < 8; ++i) b.uniform();
    CHECK(a.next_u64() == b.next_u64());
}

TEST_CASE("water_surface: the impact's pressure is gain * dF/dt, and dF/dt integrates back to the impulse m V") {
    // A 0.6 mm drop traps no bubble, so the output is the impact alone. Sum_n F[n] dt = J to rounding
    // (impact_force.hpp delivers the impulse exactly); F[n] = dt / gain * sum_{m <= n} p[m].
    const double fs = 96000.0, dt = 1.0 / fs;
    WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = fs, .sin_angle_from_vertical = 1.0});
    const double gain = 1.204 / 998.0 / (2.0 * kPi * 343.0);   // header: (rho_air / rho_w) / (2 pi r c)
    CHECK(water.impact_gain() == ameoto::test::relative(gain).epsilon(1e-12));
    Random rng(1);
    const double d = 0.6e-3, v = ameoto::terminal_speed(d);
    water.strike(d, v, rng);
    CHECK(water.active_bubbles() == 0);
    CHECK(water.active_impacts() == 1);
    std::vector<double> p(400);
    water.process(p.data(), 400);
    double force = 0.0, impulse = 0.0, peak = 0.0;
    for (double x : p) {
        force += x * dt / gain;
        impulse += force * dt;
        peak = std::max(peak, std::abs(x));
    }
    const double m = 998.0 * kPi / 6.0 * d * d * d;
    CHECK(impulse == ameoto::test::relative(m * v).epsilon(1e-9));
    CHECK(std::abs(force) < 1e-9 * m * v / dt);   // the force is over: back to 0
    CHECK(water.active_impacts() == 0);
    MESSAGE("0.6 mm drop at ", v, " m/s: impact peak ", peak, " Pa at 1 m (", 20.0 * std::log10(peak / 2e-5), " dB SPL)");
    // Directivity: half the sine, half the pressure.
    WaterSurface half(WaterSurfaceConfig{.sample_rate_hz = fs, .sin_angle_from_vertical = 0.5});
    Random rng2(1);
    half.strike(d, v, rng2);
    std::vector<double> q(400);
    half.process(q.data(), 400);
    for (std::size_t i = 0; i < p.size(); ++i) CHECK(q[i] == doctest::Approx(0.5 * p[i]).epsilon(1e-12));
}

TEST_CASE("water_surface: light rain (1 and 2 mm/h) on 1 m^2 at 96 kHz peaks in 13-25 kHz") {
    // physics.md section 5, check 10. Rain from RainSpawner (Marshall-Palmer, 0.5-6 mm, Poisson arrivals)
    // with Gunn-Kinzer speeds, 20 s (about 15 000 drops at 1 mm/h). Average power spectrum: Welch, Hann,
    // 4096 points (23 Hz bins), then a 1 kHz moving average: single bubbles ring in lines about
    // d / pi = 70-900 Hz wide, and the 1 kHz band level is what rain-noise spectra report (the raw
    // maximum is also printed). The peak must lie in 13-25 kHz.
    const double fs = 96000.0;
    for (double rate : {1.0, 2.0}) {
        CAPTURE(rate);
        const RainRender r = rain_on_water(rate, 1.0, 20.0, fs, 2024);
        REQUIRE(std::all_of(r.samples.begin(), r.samples.end(), [](double x) { return std::isfinite(x); }));
        const std::size_t size = 4096;
        const std::vector<double> power = welch(r.samples, size);
        const double bin_hz = fs / static_cast<double>(size);
        const int half = static_cast<int>(std::lround(500.0 / bin_hz));
        std::vector<double> smooth(power.size(), 0.0);
        for (int k = 0; k < static_cast<int>(power.size()); ++k) {
            double sum = 0.0;
            int count = 0;
            for (int j = std::max(0, k - half); j <= std::min(static_cast<int>(power.size()) - 1, k + half); ++j, ++count) sum += power[static_cast<std::size_t>(j)];
            smooth[static_cast<std::size_t>(k)] = sum / count;
        }
        const auto from = static_cast<std::ptrdiff_t>(std::lround(500.0 / bin_hz));   // above 500 Hz
        const auto peak = std::max_element(smooth.begin() + from, smooth.end()) - smooth.begin();
        const auto raw_peak = std::max_element(power.begin() + from, power.end()) - power.begin();
        const double f_peak = static_cast<double>(peak) * bin_hz;
        // Below 10 kHz: the strongest 1 kHz band there, against the peak.
        const auto low = std::max_element(smooth.begin() + from, smooth.begin() + static_cast<std::ptrdiff_t>(10e3 / bin_hz)) - smooth.begin();
        double p2 = 0.0;
        for (double x : r.samples) p2 += x * x;
        const auto& s = r.stats;
        MESSAGE(rate, " mm/h: ", s.strikes, " drops, ", s.bubbles_started, " bubbles (small ", s.by_class[1],
                " drops, medium ", s.by_class[2], ", large ", s.by_class[3], "); spectral peak ", f_peak,
                " Hz (raw bin ", static_cast<double>(raw_peak) * bin_hz, " Hz); strongest band below 10 kHz at ",
                static_cast<double>(low) * bin_hz, " Hz, ", 10.0 * std::log10(smooth[static_cast<std::size_t>(low)] / smooth[static_cast<std::size_t>(peak)]),
                " dB re peak; level ", 10.0 * std::log10(p2 / static_cast<double>(r.samples.size()) / 4e-10), " dB SPL at 1 m");
        CHECK(f_peak >= 13e3);
        CHECK(f_peak <= 25e3);
        CHECK(s.bubbles_dropped == 0);
    }
}

TEST_CASE("water_surface: the same seed gives the same samples, at any block size") {
    const RainRender a = rain_on_water(20.0, 1.0, 1.0, 48000.0, 77, 1);
    const RainRender b = rain_on_water(20.0, 1.0, 1.0, 48000.0, 77, 1);
    CHECK(a.samples == b.samples);
    const RainRender c = rain_on_water(20.0, 1.0, 1.0, 48000.0, 78, 1);
    CHECK(a.samples != c.samples);
    CHECK(a.stats.bubbles_started > 10);

    // Block size: strikes at the same samples, processed 1, 7, 64 or 256 frames at a time (and through
    // sample() and the float path) give identical samples.
    auto render = [](int block, int mode) {
        WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = 48000.0});
        Random rng(5);
        std::vector<double> out(24000, 0.0);
        std::vector<float> f(24000, 0.0f);
        for (int n = 0; n < 24000; n += block) {
            for (int k = n; k < n + block; ++k)
                if (k % 97 == 0) water.strike((0.6 + 0.03 * (k % 113)) * 1e-3, 5.0, rng);
            const int count = std::min(block, 24000 - n);
            if (mode == 0) water.process(out.data() + n, count);
            if (mode == 1)
                for (int k = 0; k < count; ++k) out[static_cast<std::size_t>(n + k)] = water.sample();
            if (mode == 2) water.process(f.data() + n, count);
        }
        if (mode == 2)
            for (std::size_t i = 0; i < out.size(); ++i) out[i] = f[i];
        return out;
    };
    // Strikes fall on multiples of 97 within each block: use block sizes that divide into the strike
    // pattern the same way (strikes land at a block's start), i.e. block 1, or blocks whose starts
    // include every multiple of 97.
    const std::vector<double> reference = render(1, 0);
    CHECK(render(97, 0) == reference);
    CHECK(render(1, 1) == reference);
    std::vector<double> as_float = render(97, 2), rounded(reference.size());
    for (std::size_t i = 0; i < reference.size(); ++i) rounded[i] = static_cast<float>(reference[i]);
    CHECK(as_float == rounded);
    double energy = 0.0;
    for (double x : reference) energy += x * x;
    CHECK(energy > 0.0);
}

TEST_CASE("water_surface: a full bubble pool drops the new bubble and counts it") {
    WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = 96000.0, .max_bubbles = 4});
    Random rng(3);
    for (int i = 0; i < 100; ++i) water.strike(0.9e-3, 3.7, rng);   // small drops: 95 % trap a bubble
    const auto& s = water.stats();
    CHECK(water.active_bubbles() == 4);
    CHECK(s.bubbles_started == 4);
    CHECK(s.bubbles_entrained > 80);
    CHECK(s.bubbles_dropped == s.bubbles_entrained - 4);
    std::vector<double> x(96000);
    water.process(x.data(), 96000);   // they ring out
    CHECK(water.active_bubbles() == 0);
    water.strike(0.9e-3, 3.7, rng);
    CHECK(water.stats().bubbles_started + water.stats().bubbles_dropped == water.stats().bubbles_entrained);
    water.reset();
    CHECK(water.active_bubbles() == 0);
    CHECK(water.active_impacts() == 0);
    CHECK(water.sample() == 0.0);
}

TEST_CASE("water_surface: heavy rain with every drop size stays finite; at 48 kHz the bubbles above 21.6 kHz are not played") {
    const RainRender r = rain_on_water(100.0, 1.0, 2.0, 48000.0, 99);
    REQUIRE(std::all_of(r.samples.begin(), r.samples.end(), [](double x) { return std::isfinite(x); }));
    double peak = 0.0;
    for (double x : r.samples) peak = std::max(peak, std::abs(x));
    CHECK(peak > 0.0);
    CHECK(peak < 10.0);   // bubbles are mPa, tens of mPa at most; impacts below that
    CHECK(r.stats.bubbles_above_band > 0);
    CHECK(r.stats.bubbles_dropped == 0);
    CHECK(r.stats.impacts_dropped == 0);
    CHECK(r.stats.by_class[3] > 0);
}

TEST_CASE("water_surface: bad configurations are refused with a reason") {
    CHECK_THROWS_AS(WaterSurface(WaterSurfaceConfig{.sample_rate_hz = 100.0}), std::invalid_argument);
    CHECK_THROWS_AS(WaterSurface(WaterSurfaceConfig{.sample_rate_hz = NAN}), std::invalid_argument);
    CHECK_THROWS_AS(WaterSurface(WaterSurfaceConfig{.max_bubbles = 0}), std::invalid_argument);
    CHECK_THROWS_AS(WaterSurface(WaterSurfaceConfig{.sin_angle_from_vertical = 1.5}), std::invalid_argument);
    CHECK_NOTHROW(WaterSurface(WaterSurfaceConfig{}));
}

TEST_CASE("water_surface: strike, sample and process neither allocate nor lock (rt audit)") {
    WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = 48000.0, .max_bubbles = 8});
    Random rng(42);
    std::vector<double> out(256);
    std::vector<float> outf(1000);
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int i = 0; i < 40; ++i) {
            water.strike((0.5 + 0.1 * i) * 1e-3, 2.0 + 0.2 * i, rng);   // every class, 0.5-4.4 mm
            if (i % 4 == 0)
                for (int k = 0; k < 12; ++k) water.strike(0.9e-3, 3.7, rng);   // overflows the pool of 8
            water.process(out.data(), 256);
        }
        water.strike(1.0e-3, 4.0, rng);
        water.strike(NAN, 4.0, rng);
        water.process(outf.data(), 1000);
        (void)water.sample();
        (void)water.stats();
        water.reset();
    }
    CHECK(audit.entries() > 0);
    CHECK_MESSAGE(audit.violations() == 0, audit.first());
    CHECK(water.stats().bubbles_dropped > 0);
}

TEST_CASE("water_surface: cost per ringing bubble per sample") {
    // Figures for docs/surfaces.md, not pass/fail bounds beyond a generous sanity limit.
    // The machine may be shared: each figure is the best of 5 runs.
    // (1) The bubble loop alone: 256 bubbles of 3 mm (about 100 ms each), 256-sample blocks at 48 kHz.
    std::vector<ameoto::Bubble> bubbles(256);
    std::vector<double> out(256, 0.0);
    const int blocks = 16;
    double per_bubble = 1e9;
    for (int run = 0; run < 5; ++run) {
        for (auto& b : bubbles) REQUIRE(b.start(3e-3, 0.05, 48000.0));
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < blocks; ++k)
            for (auto& b : bubbles) b.render_add(out.data(), 256);
        const auto t1 = std::chrono::steady_clock::now();
        for (const auto& b : bubbles) REQUIRE(b.active());
        per_bubble = std::min(per_bubble, std::chrono::duration<double, std::nano>(t1 - t0).count() / (256.0 * blocks * 256));
    }
    // (2) The whole surface under 50 mm/h on 1 m^2 at 48 kHz (impacts, pool, compaction included):
    // time per sample over the mean number of ringing bubbles.
    ameoto::RainSpawner rain(ameoto::RainSpawner::Config{.area_m2 = 1.0});
    rain.set_rate_now(50.0);
    WaterSurface water(WaterSurfaceConfig{.sample_rate_hz = 48000.0});
    Random rng(8);
    const int frames = 48000;
    std::vector<int> arrivals(frames);
    std::vector<double> diameters;
    for (int n = 0; n < frames; ++n) {
        arrivals[static_cast<std::size_t>(n)] = rain.advance(1.0 / 48000.0, rng);
        for (int i = 0; i < arrivals[static_cast<std::size_t>(n)]; ++i) diameters.push_back(rain.sample_diameter_m(rng));
    }
    double busy = 0.0, ns = 1e300;
    for (int run = 0; run < 5; ++run) {
        WaterSurface w(WaterSurfaceConfig{.sample_rate_hz = 48000.0});
        Random r(8);
        double total = 0.0;
        busy = 0.0;
        std::size_t next = 0;
        for (int n = 0; n < frames; n += 64) {
            for (int k = n; k < n + 64; ++k)
                for (int i = 0; i < arrivals[static_cast<std::size_t>(k)]; ++i, ++next)
                    w.strike(diameters[next], ameoto::terminal_speed(diameters[next]), r);
            const auto a = std::chrono::steady_clock::now();
            w.process(out.data(), 64);
            const auto b = std::chrono::steady_clock::now();
            total += std::chrono::duration<double, std::nano>(b - a).count();
            busy += w.active_bubbles() * 64.0;
        }
        ns = std::min(ns, total);
        water = std::move(w);
    }
    MESSAGE("cost: ", per_bubble, " ns per bubble per sample (bubble loop); 50 mm/h on 1 m^2: ", ns / frames,
            " ns per sample with ", busy / frames, " bubbles ringing on average, ", water.stats().strikes, " drops");
    AMEOTO_CHECK_UNLESS_SANITIZED(per_bubble < 200.0);   // a cost bound on the normal build only
}
