// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/binaural_design.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/biquad.hpp"
#include "engine/core/fft.hpp"
#include "engine/core/physical_constants.hpp"

namespace ameoto::binaural_design {

namespace {

// Every signed permutation of (a, a, b) (Lebedev's orbit b_k), or of (a, a, a), (0, a, a), (1, 0, 0).
void lebedev_add_orbit(std::vector<SpherePoint>& out, double a, double b, int kind, double weight) {
    std::vector<std::array<double, 3>> pts;
    auto signs = [&](std::array<double, 3> p) {
        for (int s = 0; s < 8; ++s) {
            std::array<double, 3> q{(s & 1) ? -p[0] : p[0], (s & 2) ? -p[1] : p[1], (s & 4) ? -p[2] : p[2]};
            if (std::find(pts.begin(), pts.end(), q) == pts.end()) pts.push_back(q);
        }
    };
    if (kind == 1) {                       // (1, 0, 0): 6
        signs({1, 0, 0}); signs({0, 1, 0}); signs({0, 0, 1});
    } else if (kind == 2) {                // (0, a, a): 12
        signs({0, a, a}); signs({a, 0, a}); signs({a, a, 0});
    } else if (kind == 3) {                // (a, a, a): 8
        signs({a, a, a});
    } else {                               // (a, a, b): 24
        signs({a, a, b}); signs({a, b, a}); signs({b, a, a});
    }
    for (const auto& p : pts) out.push_back({p[0], p[1], p[2], weight});
}

// Legendre polynomial P_n(x) by the three-term recurrence.
double binaural_legendre(int n, double x) {
    double p0 = 1.0, p1 = x;
    if (n == 0) return p0;
    for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    return p1;
}

// RBJ cookbook low-pass / high-pass, Q = 1/sqrt(2) (Butterworth), run in place (direct form I).
void crossover_run(const Biquad& q, std::vector<double>& x) {
    BiquadState state;
    for (double& v : x) v = state.process(q, v);
}

}  // namespace

std::vector<SpherePoint> lebedev_50() {
    // Weights and the b1 orbit's coordinates: Lebedev & Laikov (1999), the 50-point rule (as in their
    // published Fortran/C generator, LD0050).
    std::vector<SpherePoint> out;
    lebedev_add_orbit(out, 0, 0, 1, 0.1269841269841270e-1);
    lebedev_add_orbit(out, 1.0 / std::sqrt(2.0), 0, 2, 0.2257495590828924e-1);
    lebedev_add_orbit(out, 1.0 / std::sqrt(3.0), 0, 3, 0.2109375000000000e-1);
    lebedev_add_orbit(out, 1.0 / std::sqrt(11.0), 3.0 / std::sqrt(11.0), 4, 0.2017333553791887e-1);
    return out;
}

void ambix_sn3d(int order, double x, double y, double z, double* out) {
    if (order < 0 || order > 3) throw std::invalid_argument("ambix_sn3d: order must be 0..3");
    out[0] = 1.0;
    if (order < 1) return;
    out[1] = y;
    out[2] = z;
    out[3] = x;
    if (order < 2) return;
    const double s3 = std::sqrt(3.0);
    out[4] = s3 * x * y;
    out[5] = s3 * y * z;
    out[6] = 0.5 * (3.0 * z * z - 1.0);
    out[7] = s3 * x * z;
    out[8] = 0.5 * s3 * (x * x - y * y);
    if (order < 3) return;
    const double s58 = std::sqrt(5.0 / 8.0), s38 = std::sqrt(3.0 / 8.0), s15 = std::sqrt(15.0);
    out[9] = s58 * y * (3.0 * x * x - y * y);
    out[10] = s15 * x * y * z;
    out[11] = s38 * y * (5.0 * z * z - 1.0);
    out[12] = 0.5 * z * (5.0 * z * z - 3.0);
    out[13] = s38 * x * (5.0 * z * z - 1.0);
    out[14] = 0.5 * s15 * z * (x * x - y * y);
    out[15] = s58 * x * (x * x - 3.0 * y * y);
}

std::vector<double> max_re_weights(int order) {
    const double angle = 137.9 * constants::pi / 180.0 / (order + 1.51);
    std::vector<double> g(static_cast<std::size_t>(order + 1));
    double energy = 0.0;
    for (int n = 0; n <= order; ++n) {
        g[static_cast<std::size_t>(n)] = binaural_legendre(n, std::cos(angle));
        energy += (2.0 * n + 1.0) * g[static_cast<std::size_t>(n)] * g[static_cast<std::size_t>(n)];
    }
    const double scale = std::sqrt((order + 1.0) * (order + 1.0) / energy);
    for (double& v : g) v *= scale;
    return g;
}

void linkwitz_riley_4(const std::vector<double>& x, double fc_hz, double rate_hz, std::vector<double>& lp,
                      std::vector<double>& hp) {
    const Biquad l = butterworth_section(false, fc_hz, rate_hz, 1.0 / std::sqrt(2.0));
    const Biquad h = butterworth_section(true, fc_hz, rate_hz, 1.0 / std::sqrt(2.0));
    lp = x;
    crossover_run(l, lp);
    crossover_run(l, lp);
    hp = x;
    crossover_run(h, hp);
    crossover_run(h, hp);
}

int linkwitz_riley_4_tail(double fc_hz, double rate_hz, double eps) {
    const int span = static_cast<int>(std::ceil(rate_hz));   // a second: far past any audible crossover's ring
    std::vector<double> impulse(static_cast<std::size_t>(span), 0.0), lp, hp;
    impulse[0] = 1.0;
    linkwitz_riley_4(impulse, fc_hz, rate_hz, lp, hp);
    double peak = 0.0;
    for (int t = 0; t < span; ++t) peak = std::max({peak, std::abs(lp[static_cast<std::size_t>(t)]), std::abs(hp[static_cast<std::size_t>(t)])});
    int last = 0;
    for (int t = 0; t < span; ++t)
        if (std::abs(lp[static_cast<std::size_t>(t)]) > eps * peak || std::abs(hp[static_cast<std::size_t>(t)]) > eps * peak) last = t;
    return last + 1;
}

std::vector<double> minimum_phase_fir(const std::vector<double>& magnitude, int taps) {
    const std::size_t half = magnitude.size() - 1;
    const std::size_t K = 2 * half;
    if (magnitude.size() < 3 || (K & (K - 1)) != 0 || taps < 1 || static_cast<std::size_t>(taps) > K)
        throw std::invalid_argument("minimum_phase_fir: K/2+1 bins with K a power of two, 1 <= taps <= K");
    // Real cepstrum of log |H| (even, real): c = IDFT(log |H|). The inverse DFT is conj(DFT(conj(x))) / K.
    std::vector<std::complex<double>> a(K);
    for (std::size_t k = 0; k <= half; ++k) {
        a[k] = std::log(std::max(magnitude[k], 1e-30));
        if (k > 0 && k < half) a[K - k] = a[k];
    }
    fft_in_place(a);   // log |H| is real and even: its DFT is real and even, and equals K times the IDFT
    for (auto& v : a) v = std::complex<double>(v.real() / static_cast<double>(K), 0.0);
    // Fold: keep quefrency 0 and K/2, double 1..K/2-1, drop the negative ones; exp of its DFT is H_min.
    for (std::size_t n = 1; n < half; ++n) {
        a[n] *= 2.0;
        a[K - n] = 0.0;
    }
    fft_in_place(a);
    for (auto& v : a) v = std::exp(v);
    for (auto& v : a) v = std::conj(v);
    fft_in_place(a);   // conj(DFT(conj(H))) / K: the impulse response
    std::vector<double> h(static_cast<std::size_t>(taps));
    const int fade = std::max(1, taps / 4);
    for (int t = 0; t < taps; ++t) {
        double w = 1.0;
        if (t >= taps - fade) w = 0.5 * (1.0 + std::cos(constants::pi * (t - (taps - fade) + 1) / fade));
        h[static_cast<std::size_t>(t)] = w * a[static_cast<std::size_t>(t)].real() / static_cast<double>(K);
    }
    return h;
}

}  // namespace ameoto::binaural_design
