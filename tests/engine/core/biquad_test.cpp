// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/biquad.hpp: the cookbook Butterworth sections against the analogue Butterworth
// magnitude through the bilinear transform, and the state against the section's response.
#include "engine/core/biquad.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <complex>

#include "engine/core/physical_constants.hpp"

using ameoto::Biquad;
using ameoto::BiquadState;
using ameoto::butterworth_section;

namespace {

constexpr double rate = 48000.0;
constexpr double pi = ameoto::constants::pi;

std::complex<double> at_hz(const Biquad& q, double hz) { return q.response(std::polar(1.0, 2.0 * pi * hz / rate)); }

// The bilinear transform maps f to the analogue frequency tan(pi f / rate), the corner to tan(pi fc /
// rate): an order-2 Butterworth's |H|^2 is 1 / (1 + (W / Wc)^4) low-pass, (W / Wc)^4 / (1 + (W / Wc)^4) high.
double butterworth2_power(bool high, double hz, double corner_hz) {
    const double w = std::tan(pi * hz / rate) / std::tan(pi * corner_hz / rate);
    const double w4 = w * w * w * w;
    return high ? w4 / (1.0 + w4) : 1.0 / (1.0 + w4);
}

}  // namespace

TEST_CASE("biquad: Q = 1/sqrt 2 sections are the order-2 Butterworth, warped by the bilinear transform") {
    for (const bool high : {false, true}) {
        for (const double corner : {100.0, 1348.0, 9000.0}) {
            const Biquad q = butterworth_section(high, corner, rate, 1.0 / std::sqrt(2.0));
            CAPTURE(high);
            CAPTURE(corner);
            CHECK(std::abs(at_hz(q, corner)) == doctest::Approx(std::sqrt(0.5)).epsilon(1e-9));   // -3 dB at the corner
            for (const double hz : {10.0, 50.0, 500.0, 2000.0, 12000.0, 23000.0})
                CHECK(std::norm(at_hz(q, hz)) == doctest::Approx(butterworth2_power(high, hz, corner)).epsilon(1e-8).scale(1e-12));
            // DC and Nyquist: a low-pass passes DC and nulls Nyquist, a high-pass the reverse.
            CHECK(std::abs(q.response(1.0)) == doctest::Approx(high ? 0.0 : 1.0).scale(1.0).epsilon(1e-12));
            CHECK(std::abs(q.response(-1.0)) == doctest::Approx(high ? 1.0 : 0.0).scale(1.0).epsilon(1e-12));
        }
    }
}

TEST_CASE("biquad: the state's steady sine is the section's response at that frequency") {
    const Biquad q = butterworth_section(false, 1000.0, rate, 0.54);   // any Q: an order-4 section's
    for (const double hz : {300.0, 1000.0, 3000.0}) {
        BiquadState s;
        const double w = 2.0 * pi * hz / rate;
        // Run 2 s (the poles' decay is far shorter), then fit the last period's amplitude and phase.
        const int settle = static_cast<int>(2.0 * rate);
        for (int n = 0; n < settle; ++n) s.process(q, std::sin(w * n));
        std::complex<double> fit = 0.0;
        const int length = 4800;   // 0.1 s: whole periods of every frequency here
        for (int n = settle; n < settle + length; ++n) fit += s.process(q, std::sin(w * n)) * std::polar(1.0, -w * n);
        fit *= 2.0 / length;   // y = |H| sin(w n + arg H): its projection on e^(-i w n) is |H| e^(i arg H) / (2i)
        const std::complex<double> measured = fit * std::complex<double>(0.0, 1.0);
        const std::complex<double> expected = at_hz(q, hz);
        CAPTURE(hz);
        CHECK(std::abs(measured - expected) < 1e-6 * std::abs(expected) + 1e-9);
    }
}

TEST_CASE("biquad: a fresh state is silent and the identity section passes its input") {
    BiquadState s;
    const Biquad identity;
    for (int n = 0; n < 8; ++n) CHECK(s.process(identity, 0.25 * n) == 0.25 * n);
    BiquadState quiet;
    const Biquad q = butterworth_section(true, 500.0, rate, 0.7);
    for (int n = 0; n < 8; ++n) CHECK(quiet.process(q, 0.0) == 0.0);
}
