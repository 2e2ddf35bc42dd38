// SPDX-License-Identifier: GPL-3.0-or-later
// The matrix-pencil fit (engine/reference/matrix_pencil.hpp) against synthetic sums of damped sinusoids
// whose frequencies, dampings and amplitudes are known: the estimator of the canopy's panel modes in air.
#include "engine/reference/matrix_pencil.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "engine/core/physical_constants.hpp"

namespace pencil_test {

using ameoto::reference::DampedSinusoid;

std::vector<double> synthesise(const std::vector<DampedSinusoid>& parts, double dt, double seconds) {
    std::vector<double> x(static_cast<std::size_t>(seconds / dt));
    for (std::size_t n = 0; n < x.size(); ++n) {
        const double t = dt * static_cast<double>(n);
        for (const DampedSinusoid& c : parts)
            x[n] += c.amplitude * std::exp(-c.damping_per_s * t) *
                    std::cos(2.0 * ameoto::constants::pi * c.frequency_hz * t + c.phase_rad);
    }
    return x;
}

// White Gaussian noise by Box-Muller from mt19937_64's raw output (the same numbers on every library).
void add_noise(std::vector<double>& x, double rms, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    auto uniform = [&] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
    for (double& v : x) v += rms * std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * ameoto::constants::pi * uniform());
}

// The fitted component nearest `f`.
DampedSinusoid nearest(const std::vector<DampedSinusoid>& fit, double f) {
    DampedSinusoid best;
    for (const DampedSinusoid& c : fit)
        if (std::abs(c.frequency_hz - f) < std::abs(best.frequency_hz - f)) best = c;
    return best;
}

constexpr double kPencilDt = 1.0 / 40000.0;   // the fast model's projections' sampling (canopy_in_air.cpp)


TEST_CASE("matrix pencil: a close pair 5 % apart among strong components outside the band") {
    // 300 and 315 Hz in a 0.1 s record (1 / T = 10 Hz: a Hann window's peak is 40 Hz wide, so it sees one).
    const std::vector<DampedSinusoid> parts = {
        {300.0, 4.0, 1.0, 0.3}, {315.0, 9.0, 0.6, -1.2}, {60.0, 2.0, 3.0, 0.0}, {900.0, 20.0, 2.0, 1.0}};
    const std::vector<double> x = synthesise(parts, kPencilDt, 0.1);
    ameoto::reference::PencilSettings s;
    s.f_lo_hz = 200.0;
    s.f_hi_hz = 420.0;
    const std::vector<DampedSinusoid> fit = ameoto::reference::fit_damped_sinusoids(x, kPencilDt, s);
    // Noise-free: the fit is limited by the 80 dB low-pass's leak of the 60 and 900 Hz components (3 and 2
    // times the pair's amplitude) and by round-off; bounds set about ten times above what is measured.
    for (int i = 0; i < 2; ++i) {
        const DampedSinusoid want = parts[static_cast<std::size_t>(i)], got = nearest(fit, want.frequency_hz);
        CHECK(got.frequency_hz == doctest::Approx(want.frequency_hz).epsilon(1e-5));
        CHECK(got.damping_per_s == ameoto::test::relative(want.damping_per_s).epsilon(0.01));
        CHECK(got.amplitude == ameoto::test::relative(want.amplitude).epsilon(1e-3));
        CHECK(std::abs(std::remainder(got.phase_rad - want.phase_rad, 2.0 * ameoto::constants::pi)) < 1e-3);   // radians, absolute
    }
    // Whatever else the pencil keeps (the leak, at most) holds under 1e-6 of the record's energy.
    double rest = 0.0, total = 0.0;
    for (const DampedSinusoid& c : fit) {
        const double e = ameoto::reference::record_energy(c, 0.1);
        total += e;
        if (std::abs(c.frequency_hz - 300.0) > 0.5 && std::abs(c.frequency_hz - 315.0) > 0.5) rest += e;
    }
    CHECK(rest < 1e-6 * total);
    const double e300 = ameoto::reference::record_energy(parts[0], 0.1), e315 = ameoto::reference::record_energy(parts[1], 0.1);
    CHECK(ameoto::reference::energy_weighted_frequency(fit, 0.1) == doctest::Approx((300.0 * e300 + 315.0 * e315) / (e300 + e315)).epsilon(1e-5));
}

TEST_CASE("matrix pencil: eight close components (a canopy cluster) in noise") {
    // The shape of the fast model's panel mode 4: eight canopy modes 266-337 Hz, 7-15 Hz apart, dampings
    // 1-8 /s, in white noise 40 dB under the strongest component's amplitude (rms 1 % of it), over 0.4 s
    // (the record of `ameoto reference canopy`: in 0.1 s, 1 / T = 10 Hz, the pencil cannot separate them).
    const std::vector<DampedSinusoid> parts = {{266.0, 3.0, 0.3, 0.1},  {279.0, 2.0, 0.5, 2.0}, {288.0, 5.0, 1.0, -0.4},
                                               {297.0, 1.0, 0.4, 1.1},  {307.0, 4.0, 0.9, 0.7}, {322.0, 6.0, 0.8, -2.0},
                                               {330.0, 8.0, 0.7, 2.5},  {337.0, 2.0, 0.2, -1.0}};
    std::vector<double> x = synthesise(parts, kPencilDt, 0.4);
    add_noise(x, 0.01, 19);
    ameoto::reference::PencilSettings s;
    s.f_lo_hz = 200.0;
    s.f_hi_hz = 420.0;
    s.relative_threshold = 1e-4;   // as panel_mode_components
    const std::vector<DampedSinusoid> fit = ameoto::reference::fit_damped_sinusoids(x, kPencilDt, s);
    // Bounds: several times the errors measured (under 0.07 Hz and 1.5 % at three times this noise; Hua &
    // Sarkar: the pencil's variance stays near the Cramer-Rao bound at this SNR).
    for (const DampedSinusoid& want : parts) {
        const DampedSinusoid got = nearest(fit, want.frequency_hz);
        CAPTURE(want.frequency_hz);
        CHECK(std::abs(got.frequency_hz - want.frequency_hz) < 0.2);
        CHECK(std::abs(got.amplitude / want.amplitude - 1.0) < 0.05);
    }
    double weighted = 0.0, total = 0.0;
    for (const DampedSinusoid& c : parts) {
        const double e = ameoto::reference::record_energy(c, 0.4);
        weighted += e * c.frequency_hz;
        total += e;
    }
    CHECK(ameoto::reference::energy_weighted_frequency(fit, 0.4) == doctest::Approx(weighted / total).epsilon(0.002));
}

TEST_CASE("matrix pencil: bad settings are refused") {
    const std::vector<double> x(4000, 0.0);
    ameoto::reference::PencilSettings s;
    s.f_lo_hz = 300.0;
    s.f_hi_hz = 200.0;
    CHECK_THROWS_AS(ameoto::reference::fit_damped_sinusoids(x, kPencilDt, s), std::invalid_argument);
    s.f_lo_hz = 100.0;
    s.f_hi_hz = 30000.0;   // above the Nyquist frequency
    CHECK_THROWS_AS(ameoto::reference::fit_damped_sinusoids(x, kPencilDt, s), std::invalid_argument);
    s.f_hi_hz = 200.0;
    s.start_s = 0.2;   // after the record
    CHECK_THROWS_AS(ameoto::reference::fit_damped_sinusoids(x, kPencilDt, s), std::invalid_argument);
    s.start_s = 0.0;
    CHECK(ameoto::reference::fit_damped_sinusoids(x, kPencilDt, s).empty());   // silence: no component
}

}  // namespace pencil_test
