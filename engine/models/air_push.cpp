// SPDX-License-Identifier: GPL-3.0-or-later
// The compressible push's crossover and filters: see air_push.hpp for the equations.
#include "engine/models/air_push.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/fft.hpp"
#include "engine/core/physical_constants.hpp"

namespace ameoto {

namespace {

using cplx = std::complex<double>;

constexpr double above_top_mode = 1.2;     // the corner over the highest mode
constexpr double highest_corner = 0.3;     // of the rate
constexpr double lead_s = 0.5e-3;          // each filter's start before the modes' bulk delay D
constexpr double length_s = 4.7e-3;        // each filter's length after D: the high half rings about 5.4 / corner
constexpr double period_s = 0.02;          // the design's frequency grid: 1 / period apart
constexpr double roll_from = 0.35, roll_to = 0.45;   // of the rate: the filters' own roll-off
constexpr double low_reach = 4.0;          // the instantaneous push's bins: to this many corners

double fall(double f, double from, double to) {
    if (f <= from) return 1.0;
    if (f >= to) return 0.0;
    return 0.5 * (1.0 + std::cos(constants::pi * (f - from) / (to - from)));
}

}  // namespace

PushCrossover push_crossover(const AirCanopyModes& m) {
    PushCrossover x;
    double top_hz = 0.0;
    for (Eigen::Index k = 0; k < m.omega.size(); ++k) top_hz = std::max(top_hz, m.omega[k] / (2.0 * constants::pi));
    const double rate = 1.0 / m.time_step_s;
    const double corner = above_top_mode * top_hz;
    if (!(top_hz > 0.0) || corner > highest_corner * rate) return x;
    x.hz = corner;
    // Butterworth of order 4: sections of q = 1 / (2 cos(pi / 8)) and 1 / (2 cos(3 pi / 8)); twice over.
    const double q[2] = {1.0 / (2.0 * std::cos(constants::pi / 8.0)), 1.0 / (2.0 * std::cos(3.0 * constants::pi / 8.0))};
    for (int i = 0; i < 4; ++i) {
        x.low[i] = butterworth_section(false, corner, rate, q[i % 2]);
        x.high[i] = butterworth_section(true, corner, rate, q[i % 2]);
    }
    return x;
}

// J1 by Abramowitz & Stegun's polynomial approximations (9.4.4 for |x| <= 3, error under 1.3e-8 in
// J1(x) / x; 9.4.6 above, under 4e-8 in the modulus and 9e-8 in the phase): a filter design calls it for
// every node and bin (200 000 times a listening point), where std::cyl_bessel_j took 45 ms.
double tile_directivity(double k_a_sin_theta) {
    const double x = std::abs(k_a_sin_theta);
    if (x <= 3.0) {
        const double y = (x / 3.0) * (x / 3.0);
        const double j1_over_x =
            0.5 + y * (-0.56249985 + y * (0.21093573 + y * (-0.03954289 + y * (0.00443319 + y * (-0.00031761 + y * 0.00001109)))));
        return 2.0 * j1_over_x;
    }
    const double u = 3.0 / x;
    const double f1 = 0.79788456 + u * (0.00000156 + u * (0.01659667 + u * (0.00017105 + u * (-0.00249511 + u * (0.00113653 + u * -0.00020033)))));
    const double theta1 = x - 2.35619449 + u * (0.12499612 + u * (0.00005650 + u * (-0.00637879 + u * (0.00074348 + u * (0.00079824 + u * -0.00029166)))));
    return 2.0 * f1 * std::cos(theta1) / (x * std::sqrt(x));
}

PushFilters design_push_filters(const AirCanopyModes& m, const PushCrossover& x, const PushScreen& screen, const PushPoint& point,
                                const AirMedium& air) {
    const auto nodes = static_cast<std::size_t>(m.nodes);
    const auto modes = static_cast<std::size_t>(m.modes);
    const std::vector<double>& areal_density = screen.areal_density;
    if (areal_density.size() != nodes || screen.tile_radius.size() != nodes || point.r.size() != nodes || point.cos_theta.size() != nodes)
        throw std::invalid_argument("push filters: one density, tile, distance and angle per node");
    if (m.instantaneous_push.rows() != m.nodes || m.instantaneous_push.cols() != m.nodes)
        throw std::invalid_argument("push filters: the modes carry no instantaneous push");
    PushFilters out;
    if (!(x.hz > 0.0)) return out;
    const double t = m.time_step_s, rate = 1.0 / t, c = air.speed_of_sound, rho = air.density;
    int n = 256;
    while (n * t < period_s) n *= 2;
    const int half = n / 2;
    const int lead = static_cast<int>(std::lround(lead_s * rate));
    out.taps = static_cast<int>(std::lround((lead_s + length_s) * rate));

    // What every node shares at each bin: the roll-off, the force held over the step, 1 / (4 pi); and the
    // two halves.
    std::vector<cplx> common(static_cast<std::size_t>(half + 1)), low(common.size()), high(common.size());
    for (int b = 1; b <= half; ++b) {
        const double w = 2.0 * constants::pi * b * rate / n;
        const cplx z = std::polar(1.0, w * t);
        const cplx held = (z - 1.0) / cplx(0.0, w * t);
        common[static_cast<std::size_t>(b)] = fall(b * rate / n, roll_from * rate, roll_to * rate) / (4.0 * constants::pi) * held;
        cplx l = 1.0, h = 1.0;
        for (int i = 0; i < 4; ++i) {
            l *= x.low[i].response(z);
            h *= x.high[i].response(z);
        }
        low[static_cast<std::size_t>(b)] = l;
        high[static_cast<std::size_t>(b)] = h;
    }
    // The low half's part: node e's column of M_a (M + M_a)^-1 heard as point forces, each from its own
    // node at its own delay: S[e, b] = sum_i P[i, e] cos(theta_i) (1 / r_i^2 + i w / (c r_i)) e^{-i w r_i / c},
    // as two real products (P' G), bin 0 (DC) included, up to 4 x the corner: the low half is 96 dB down
    // there (and the products a fifth of all the bins' at 48 kHz).
    const int low_bins = std::min(half, static_cast<int>(std::ceil(low_reach * x.hz * n / rate)));
    Eigen::MatrixXd g_re(m.nodes, low_bins + 1), g_im(m.nodes, low_bins + 1);
    for (std::size_t i = 0; i < nodes; ++i) {
        const double r = point.r[i], cos_theta = point.cos_theta[i];
        for (int b = 0; b <= low_bins; ++b) {
            const double w = 2.0 * constants::pi * b * rate / n;
            const cplx v = cos_theta * cplx(1.0 / (r * r), w / (c * r)) * std::polar(1.0, -w * r / c);
            g_re(static_cast<Eigen::Index>(i), b) = v.real();
            g_im(static_cast<Eigen::Index>(i), b) = v.imag();
        }
    }
    const Eigen::MatrixXd s_re = m.instantaneous_push.transpose() * g_re, s_im = m.instantaneous_push.transpose() * g_im;

    out.offset.assign(nodes, 0);
    out.fir.assign(nodes * static_cast<std::size_t>(out.taps), 0.0);
    std::vector<cplx> spectrum(static_cast<std::size_t>(half + 1)), period(static_cast<std::size_t>(n));
    for (std::size_t e = 0; e < nodes; ++e) {
        const double r = point.r[e], cos_theta = point.cos_theta[e], s = areal_density[e];
        const double a_sin_theta = screen.tile_radius[e] * std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
        bool moves = false;
        for (std::size_t k = 0; k < modes && !moves; ++k) moves = m.shape[e * modes + k] != 0.0;
        // From lead samples before the node's own delay r / c: the spectrum is taken relative to it.
        const int offset = std::max(0, static_cast<int>(std::floor(r / (c * t))) - lead);
        out.offset[e] = offset;
        if (!moves || !(s > 0.0)) continue;
        const auto col = static_cast<Eigen::Index>(e);
        // The phases by recurrence, one complex product a bin (a sine and cosine a bin and node cost 40 ms a
        // listening point): e^{i w offset T} for the column, e^{i w (offset T - r / c)} for the node's own push;
        // each renewed every 64 bins, so the rounding stays under 1e-14.
        const double bin_w = 2.0 * constants::pi * rate / n;
        const cplx turn_shift = std::polar(1.0, bin_w * offset * t), turn_push = std::polar(1.0, bin_w * (offset * t - r / c));
        cplx shift = 1.0, lag = 1.0;
        spectrum[0] = cplx(s_re(col, 0), s_im(col, 0)) / (4.0 * constants::pi);   // DC: the high half 0, the low half and the held force 1
        for (int b = 1; b <= half; ++b) {
            const double w = bin_w * b;
            if (b % 64 == 0) {
                shift = std::polar(1.0, w * offset * t);
                lag = std::polar(1.0, w * (offset * t - r / c));
            } else {
                shift *= turn_shift;
                lag *= turn_push;
            }
            const cplx column = b <= low_bins ? cplx(s_re(col, b), s_im(col, b)) : cplx(0.0);
            const double beta = w * s / (2.0 * rho * c);
            const cplx push = cos_theta * cplx(1.0 / (r * r), w / (c * r)) * lag / cplx(1.0, beta * std::abs(cos_theta)) *
                              tile_directivity(w / c * a_sin_theta);
            const auto k = static_cast<std::size_t>(b);
            spectrum[k] = common[k] * (shift * low[k] * column + high[k] * push);
        }
        // The response over one period: the inverse transform of the real signal's spectrum (each bin and
        // its mirror; the roll-off is 0 at Nyquist), as the conjugate of the forward transform of the
        // conjugate.
        period[0] = spectrum[0].real();
        period[static_cast<std::size_t>(half)] = spectrum[static_cast<std::size_t>(half)].real();
        for (int b = 1; b < half; ++b) {
            period[static_cast<std::size_t>(b)] = std::conj(spectrum[static_cast<std::size_t>(b)]);
            period[static_cast<std::size_t>(n - b)] = spectrum[static_cast<std::size_t>(b)];
        }
        fft_in_place(period);
        double* fir = out.fir.data() + e * static_cast<std::size_t>(out.taps);
        const int edge = std::max(1, out.taps / 16);   // the tail's taper
        for (int tap = 0; tap < out.taps; ++tap) {
            const double sum = period[static_cast<std::size_t>(tap)].real();   // samples from the offset
            // Both ends tapered: the start over half the lead (what rings ahead of r / c is cut there), the
            // tail over its last sixteenth.
            double taper = 1.0;
            if (tap < lead / 2) taper = 0.5 * (1.0 - std::cos(constants::pi * (tap + 0.5) / (lead / 2)));
            if (tap >= out.taps - edge) taper = 0.5 * (1.0 - std::cos(constants::pi * (out.taps - tap - 0.5) / edge));
            fir[tap] = taper * sum / n;
        }
    }
    return out;
}

}  // namespace ameoto
