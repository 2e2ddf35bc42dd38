// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/bubble.hpp: one bubble's pitch, damping, chirp and level, measured from the
// rendered signal (physics.md section 5, check 8).
#include "engine/models/bubble.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

namespace {

constexpr double kRate = 96000.0;

// Minnaert, written out here from physics.md section 4 (gamma 1.4, P0 101.325 kPa, rho 998).
double minnaert_reference(double a) { return std::sqrt(3.0 * 1.4 * 101325.0 / 998.0) / (2.0 * kPi * a); }
// van den Doel's damping, physics.md section 4.
double damping_reference(double a) { return 0.13 / a + 0.0072 * std::pow(a, -1.5); }

std::vector<double> render(ameoto::Bubble& b, int frames) {
    std::vector<double> x(static_cast<std::size_t>(frames), 0.0);
    b.render_add(x.data(), frames);
    return x;
}

// Zero crossings (s) of x up to sample `last`, each found on the cubic through the four samples around it
// (bisection), so the interpolation error is far below the 1 % tolerance even at 6 samples per period.
std::vector<double> zero_crossings(const std::vector<double>& x, std::size_t last, double T) {
    std::vector<double> t;
    for (std::size_t n = 2; n + 1 < std::min(last, x.size()); ++n) {
        const double a = x[n - 1], b = x[n];
        if (!((a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0))) continue;
        // Lagrange cubic through u = -1, 0, 1, 2 (u = 0 at sample n - 1).
        const double y0 = x[n - 2], y1 = a, y2 = b, y3 = x[n + 1];
        auto p = [&](double u) {
            return -y0 * u * (u - 1) * (u - 2) / 6 + y1 * (u + 1) * (u - 1) * (u - 2) / 2 -
                   y2 * (u + 1) * u * (u - 2) / 2 + y3 * (u + 1) * u * (u - 1) / 6;
        };
        double lo = 0.0, hi = 1.0;
        const bool rising = a < 0.0;
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            ((p(mid) < 0.0) == rising ? lo : hi) = mid;
        }
        t.push_back((static_cast<double>(n - 1) + 0.5 * (lo + hi)) * T);
    }
    return t;
}

struct Measured {
    double f0 = 0.0;      // Hz, instantaneous at t = 0
    double sweep = 0.0;   // 1/s: f(t) = f0 (1 + sweep t), sweep = xi d in the model
    double d = 0.0;       // 1/s, envelope decay
    int crossings = 0;
};

// Pitch: the phase phi(t_k) = k pi + c at the zero crossings, fitted with c0 + c1 t + c2 t^2 (least
// squares), gives w(0) = c1 and the chirp c2 = w0 xi d / 2. Decay: the discrete energy operator
// x[n]^2 - x[n-1] x[n+1] = A^2 e^(-2 d t) sin^2(theta_n) (exact for a damped sinusoid; theta_n = w(t_n) T
// from the measured phase, which accounts for the chirp), so ln(E / sin^2 theta) / 2 against t has
// slope -d (least squares). Both over the first `decay_times` envelope decay times.
Measured measure(const std::vector<double>& x, double T, double window_s) {
    Measured m;
    const auto last = static_cast<std::size_t>(window_s / T);
    const std::vector<double> t = zero_crossings(x, last, T);
    m.crossings = static_cast<int>(t.size());
    REQUIRE(t.size() > 10);
    Eigen::MatrixXd A(static_cast<Eigen::Index>(t.size()), 3);
    Eigen::VectorXd y(static_cast<Eigen::Index>(t.size()));
    for (std::size_t k = 0; k < t.size(); ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        A(i, 0) = 1.0;
        A(i, 1) = t[k];
        A(i, 2) = t[k] * t[k];
        y(i) = kPi * static_cast<double>(k);
    }
    const Eigen::Vector3d c = A.colPivHouseholderQr().solve(y);
    m.f0 = c(1) / (2.0 * kPi);
    m.sweep = 2.0 * c(2) / c(1);

    double sw = 0.0, st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
    for (std::size_t n = 1; n + 1 < std::min(last, x.size()); ++n) {
        const double tn = static_cast<double>(n) * T;
        const double energy = x[n] * x[n] - x[n - 1] * x[n + 1];
        const double theta = (c(1) + 2.0 * c(2) * tn) * T;
        if (!(energy > 0.0)) continue;
        const double yn = 0.5 * std::log(energy / (std::sin(theta) * std::sin(theta)));
        sw += 1.0;
        st += tn;
        sy += yn;
        stt += tn * tn;
        sty += tn * yn;
    }
    m.d = -(sw * sty - st * sy) / (sw * stt - st * st);
    return m;
}

}  // namespace

TEST_CASE("bubble: pitch within 1 % of Minnaert and decay within 10 % of van den Doel, from the rendered signal") {
    // physics.md section 5, check 8: pitch 1 %, decay 10 %. Reference values from physics.md section 4.
    struct Case {
        double a, f_table, d_table;
    };
    for (const Case c : {Case{0.22e-3, 14.9e3, 2797.0}, Case{0.5e-3, 6.57e3, 904.0}, Case{1.0e-3, 3.29e3, 358.0}}) {
        CAPTURE(c.a);
        ameoto::Bubble b;
        REQUIRE(b.start(c.a, ameoto::bubble_pressure_amplitude_pa(c.a), kRate));
        const double d_ref = damping_reference(c.a);
        const std::vector<double> x = render(b, static_cast<int>(8.0 / d_ref * kRate) + 8);
        const Measured m = measure(x, 1.0 / kRate, 5.0 / d_ref);   // 5 decay times: 43 dB
        const double f_ref = minnaert_reference(c.a);
        MESSAGE("a = ", c.a * 1e3, " mm: f0 ", m.f0, " Hz (Minnaert ", f_ref, ", error ",
                100.0 * (m.f0 / f_ref - 1.0), " %), d ", m.d, " 1/s (van den Doel ", d_ref, ", error ",
                100.0 * (m.d / d_ref - 1.0), " %), chirp xi ", m.sweep / m.d, " from ", m.crossings, " crossings");
        CHECK(std::abs(m.f0 / f_ref - 1.0) < 0.01);
        CHECK(std::abs(m.f0 / c.f_table - 1.0) < 0.01);   // the table is rounded to 3 digits
        CHECK(std::abs(m.d / d_ref - 1.0) < 0.10);
        CHECK(std::abs(m.d / c.d_table - 1.0) < 0.10);
        // The chirp: xi = 0.1 (physics.md section 4); the fit of a small curvature, so 10 %.
        CHECK(m.sweep / m.d == ameoto::test::relative(0.1).epsilon(0.10));
        // The engine's own formulas agree with the references to rounding.
        CHECK(ameoto::minnaert_frequency_hz(c.a) == doctest::Approx(f_ref).epsilon(1e-12));
        CHECK(ameoto::bubble_damping_per_s(c.a) == ameoto::test::relative(d_ref).epsilon(1e-12));
    }
}

TEST_CASE("bubble: without the chirp it is a plain damped sinusoid at Minnaert's pitch") {
    // Tolerance 1e-3: the zero-crossing fit on a pure tone is far more precise than check 8 needs.
    const double a = 0.3e-3;
    ameoto::Bubble b;
    REQUIRE(b.start(a, 1.0, kRate, 0.0));
    const double d = damping_reference(a);
    const std::vector<double> x = render(b, static_cast<int>(6.0 / d * kRate));
    const Measured m = measure(x, 1.0 / kRate, 5.0 / d);
    CHECK(m.f0 == doctest::Approx(minnaert_reference(a)).epsilon(1e-3));
    CHECK(m.d == ameoto::test::relative(d).epsilon(1e-3));
    CHECK(std::abs(m.sweep) < 1e-3 * d);
    // The sampled formula exactly: p[n] = P e^(-d n T) sin(w0 n T), to rounding.
    const double w0 = 2.0 * kPi * minnaert_reference(a);
    double worst = 0.0;
    for (std::size_t n = 0; n < x.size(); ++n) {
        const double t = static_cast<double>(n) / kRate;
        worst = std::max(worst, std::abs(x[n] - std::exp(-d * t) * std::sin(w0 * t)));
    }
    CHECK(worst < 1e-9);
}

TEST_CASE("bubble: the recursion follows the closed form with the chirp, to rounding") {
    // p[n] = P e^(-d t) sin(w0 (t + xi d t^2 / 2)), t = n T (header); 1e-9 of P over a whole life.
    const double a = 0.22e-3, P = 2.0;
    ameoto::Bubble b;
    REQUIRE(b.start(a, P, kRate));
    const double d = damping_reference(a), w0 = 2.0 * kPi * minnaert_reference(a);
    std::vector<double> x;
    while (b.active()) x.push_back(b.sample());
    // Life: until e^(-d t) = 1e-4.
    CHECK(std::abs(static_cast<double>(x.size()) - std::log(1e4) / d * kRate) <= 1.0);
    double worst = 0.0;
    for (std::size_t n = 0; n < x.size(); ++n) {
        const double t = static_cast<double>(n) / kRate;
        worst = std::max(worst, std::abs(x[n] - P * std::exp(-d * t) * std::sin(w0 * (t + 0.05 * d * t * t))));
    }
    CHECK(worst < 1e-9 * P);
    CHECK(b.sample() == 0.0);
}

TEST_CASE("bubble: the level law, 2 rho_air (3 gamma P0 / rho_w) eps0 / r with eps0 = 1 % of 0.22 mm, scaled a^(3/2)") {
    // Header: 2.26 mPa at 1 m for 0.22 mm; a^(3/2) between radii (to rounding).
    const double p_ref = 2.0 * 1.204 * (3.0 * 1.4 * 101325.0 / 998.0) * 0.01 * 0.22e-3;
    CHECK(ameoto::bubble_pressure_amplitude_pa(0.22e-3) == ameoto::test::relative(p_ref).epsilon(1e-12));
    CHECK(p_ref == ameoto::test::relative(2.26e-3).epsilon(0.01));
    for (double a : {0.1e-3, 0.5e-3, 1e-3, 3e-3}) {
        CAPTURE(a);
        CHECK(ameoto::bubble_pressure_amplitude_pa(a) == ameoto::test::relative(p_ref * std::pow(a / 0.22e-3, 1.5)).epsilon(1e-12));
    }
    MESSAGE("amplitude at 1 m: 0.22 mm ", ameoto::bubble_pressure_amplitude_pa(0.22e-3), " Pa, 0.5 mm ",
            ameoto::bubble_pressure_amplitude_pa(0.5e-3), " Pa, 1 mm ", ameoto::bubble_pressure_amplitude_pa(1e-3), " Pa");
    // The rendered first crest is the amplitude times the envelope there (within 3 %). The crest falls
    // between samples, at 6.4 samples per period (the highest sample alone can be 12 % low), so it is read
    // by the parabola through the highest sample and its neighbours.
    ameoto::Bubble b;
    const double a = 0.22e-3, P = ameoto::bubble_pressure_amplitude_pa(a);
    REQUIRE(b.start(a, P, kRate));
    const std::vector<double> x = render(b, 8);
    const auto top = std::max_element(x.begin() + 1, x.end() - 1);
    const double y0 = *(top - 1), y1 = *top, y2 = *(top + 1);
    const double crest = y1 - (y0 - y2) * (y0 - y2) / (8.0 * (y0 - 2.0 * y1 + y2));
    const double t_crest = 0.25 / minnaert_reference(a);
    CHECK(crest == ameoto::test::relative(P * std::exp(-damping_reference(a) * t_crest)).epsilon(0.03));
}

TEST_CASE("bubble: band limit: not started at or above 0.45 fs; a bubble chirping past it fades 60 dB") {
    ameoto::Bubble b;
    // 0.13 mm: 25.3 kHz, above 0.45 * 48 kHz = 21.6 kHz.
    CHECK_FALSE(b.start(0.13e-3, 1.0, 48000.0));
    CHECK_FALSE(b.active());
    CHECK(b.start(0.13e-3, 1.0, 96000.0));
    // 0.16 mm at 48 kHz: 20.5 kHz, reaches 21.6 kHz after xi d t = 0.05, i.e. t = 0.5 / d.
    const double a = 0.16e-3, d = damping_reference(a), f0 = minnaert_reference(a);
    REQUIRE(b.start(a, 1.0, 48000.0));
    std::vector<double> x;
    while (b.active()) x.push_back(b.sample());
    const double t_fade = (21600.0 / f0 - 1.0) / (0.1 * d);
    const double t_gone = (0.49 * 48000.0 / f0 - 1.0) / (0.1 * d);   // 60 dB further down by here
    const auto n_gone = static_cast<std::size_t>(std::ceil(t_gone * 48000.0));
    CHECK(x.size() <= n_gone + 1);
    // Envelope where the fade starts: e^(-d t_fade). The last two samples are 90-100 % of the way through
    // the fade (54-60 dB down, on top of the natural decay): below 2e-3 of that, where the natural decay
    // alone would leave 0.4 of it.
    REQUIRE(x.size() > 2);
    const double tail = std::max(std::abs(x[x.size() - 1]), std::abs(x[x.size() - 2]));
    CHECK(tail < 2e-3 * std::exp(-d * t_fade));
    for (double v : x) CHECK(std::isfinite(v));
}

TEST_CASE("bubble: refuses bad arguments and stays idle") {
    ameoto::Bubble b;
    CHECK_FALSE(b.start(0.0, 1.0, kRate));
    CHECK_FALSE(b.start(-1e-3, 1.0, kRate));
    CHECK_FALSE(b.start(NAN, 1.0, kRate));
    CHECK_FALSE(b.start(1e-3, INFINITY, kRate));
    CHECK_FALSE(b.start(1e-3, 1.0, 0.0));
    CHECK_FALSE(b.start(1e-3, 1.0, kRate, -0.1));
    CHECK_FALSE(b.active());
    CHECK(b.sample() == 0.0);
    double out[4] = {1, 2, 3, 4};
    b.render_add(out, 4);
    CHECK(out[3] == 4.0);
}

TEST_CASE("bubble: the same samples at any block size") {
    const double a = 0.4e-3;
    ameoto::Bubble one, blocks;
    REQUIRE(one.start(a, 0.01, kRate));
    REQUIRE(blocks.start(a, 0.01, kRate));
    std::vector<double> x1, x2(20000, 0.0);
    for (int n = 0; n < 20000; ++n) x1.push_back(one.sample());
    for (int done = 0, size = 1; done < 20000; done += size, size = size % 300 + 7)
        blocks.render_add(x2.data() + done, std::min(size, 20000 - done));
    CHECK(x1 == x2);
}
