// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/bubble.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/physical_constants.hpp"

namespace ameoto {

namespace {

// 3 gamma P0 / rho_w (m^2/s^2): (w0 a)^2 for every Minnaert bubble.
constexpr double minnaert_constant_sq =
    3.0 * bubble::adiabatic_index * bubble::ambient_pressure_pa / constants::water_density;

// Natural log of 1000 (60 dB), used by the band-limit fade.
constexpr double ln_1000 = 6.907755278982137;

bool finite_positive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

double minnaert_frequency_hz(double radius_m) {
    return std::sqrt(minnaert_constant_sq) / (2.0 * constants::pi * radius_m);
}

double bubble_damping_per_s(double radius_m) {
    // van den Doel 2005: a in m, d in 1/s (physics.md 4).
    return 0.13 / radius_m + 0.0072 / (radius_m * std::sqrt(radius_m));
}

double bubble_pressure_amplitude_pa(double radius_m) {
    // eps0 = eta a_ref (a / a_ref)^(3/2); p = 2 rho_air (3 gamma P0 / rho_w) eps0 / r (header).
    const double ratio = radius_m / bubble::reference_radius_m;
    const double eps0 = bubble::reference_relative_amplitude * bubble::reference_radius_m * ratio * std::sqrt(ratio);
    return 2.0 * constants::air_density * minnaert_constant_sq * eps0 / bubble::reference_distance_m;
}

bool Bubble::start(double radius_m, double amplitude_pa, double sample_rate_hz, double xi) noexcept {
    remaining_ = 0;
    if (!finite_positive(radius_m) || !std::isfinite(amplitude_pa) || !finite_positive(sample_rate_hz) ||
        !std::isfinite(xi) || xi < 0.0)
        return false;
    const double f0 = minnaert_frequency_hz(radius_m);
    const double limit = bubble::band_limit * sample_rate_hz;
    if (!(f0 < limit)) return false;
    const double d = bubble_damping_per_s(radius_m);
    const double T = 1.0 / sample_rate_hz;
    const double w0 = 2.0 * constants::pi * f0;

    radius_ = radius_m;
    frequency_ = f0;
    damping_ = d;
    amplitude_ = amplitude_pa;

    // Phase increments: D[n] = w0 T + w0 xi d T^2 (n + 1/2); D[n+1] - D[n] = w0 xi d T^2.
    const double step = w0 * xi * d * T * T;
    const double first = w0 * T + 0.5 * step;
    const double r = std::exp(-d * T);
    zr_ = amplitude_pa;
    zi_ = 0.0;
    wr_ = r * std::cos(first);
    wi_ = r * std::sin(first);
    cr_ = std::cos(step);
    ci_ = std::sin(step);

    // Natural end: e^(-d t) = cutoff.
    double samples = std::ceil(std::log(1.0 / bubble::cutoff) / (d * T));
    // Band limit: f(t) = f0 (1 + xi d t) reaches the limit at t_f; from there an extra decay takes the
    // envelope down 60 dB by the time the pitch reaches fade_end.
    until_fade_ = -1;
    fade_ = 1.0;
    const double sweep = f0 * xi * d;   // Hz per second
    if (sweep > 0.0) {
        const double t_fade = (limit / f0 - 1.0) / (xi * d);
        const double fade_samples = std::ceil(t_fade / T);
        if (fade_samples < samples) {
            const double fade_duration = (bubble::fade_end - bubble::band_limit) * sample_rate_hz / sweep;   // s
            const double rate = ln_1000 / fade_duration;   // 1/s
            fade_ = std::exp(-rate * T);
            until_fade_ = std::max(1L, static_cast<long>(fade_samples));
            samples = std::min(samples, fade_samples + std::ceil(fade_duration / T));
        }
    }
    remaining_ = static_cast<long>(std::min(samples, 1e12));
    return true;
}

void Bubble::render_add(double* out, int frames) noexcept {
    while (frames > 0 && remaining_ > 0) {
        long segment = std::min<long>(frames, remaining_);
        if (until_fade_ > 0) segment = std::min(segment, until_fade_);
        double zr = zr_, zi = zi_, wr = wr_, wi = wi_;
        const double cr = cr_, ci = ci_;
        for (long n = 0; n < segment; ++n) {
            out[n] += zi;
            const double nzr = zr * wr - zi * wi;
            const double nzi = zr * wi + zi * wr;
            const double nwr = wr * cr - wi * ci;
            const double nwi = wr * ci + wi * cr;
            zr = nzr;
            zi = nzi;
            wr = nwr;
            wi = nwi;
        }
        zr_ = zr;
        zi_ = zi;
        wr_ = wr;
        wi_ = wi;
        out += segment;
        frames -= static_cast<int>(segment);
        remaining_ -= segment;
        if (until_fade_ > 0) {
            until_fade_ -= segment;
            if (until_fade_ == 0) {
                wr_ *= fade_;
                wi_ *= fade_;
                until_fade_ = -1;
            }
        }
    }
}

}  // namespace ameoto
