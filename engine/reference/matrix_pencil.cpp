// SPDX-License-Identifier: GPL-3.0-or-later
// The matrix-pencil fit of damped sinusoids: see matrix_pencil.hpp.
#include "engine/reference/matrix_pencil.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"

namespace ameoto::reference {

namespace {

// The modified Bessel function I0 by its power series (converges for the Kaiser window's beta < 20).
double bessel_i0(double x) {
    double sum = 1.0, term = 1.0;
    const double q = 0.25 * x * x;
    for (int k = 1; k < 200 && term > 1e-17 * sum; ++k) {
        term *= q / (static_cast<double>(k) * static_cast<double>(k));
        sum += term;
    }
    return sum;
}

// A Kaiser-windowed sinc low-pass (Kaiser 1974; Oppenheim & Schafer, Discrete-Time Signal Processing,
// section 7.5.3: beta and the length from the attenuation A and the transition width).
std::vector<double> kaiser_low_pass(double cutoff_hz, double transition_hz, double attenuation_db, double dt) {
    const double a = std::max(attenuation_db, 21.0);
    const double beta = a > 50.0 ? 0.1102 * (a - 8.7) : 0.5842 * std::pow(a - 21.0, 0.4) + 0.07886 * (a - 21.0);
    const double width = 2.0 * constants::pi * transition_hz * dt;   // rad per sample
    const int order = std::max(2, static_cast<int>(std::ceil((a - 8.0) / (2.285 * width))));
    std::vector<double> h(static_cast<std::size_t>(order + 1));
    const double fc = 2.0 * cutoff_hz * dt, i0b = bessel_i0(beta);
    for (int j = 0; j <= order; ++j) {
        const double m = j - 0.5 * order, r = 2.0 * j / order - 1.0;
        const double sinc = m == 0.0 ? 1.0 : std::sin(constants::pi * fc * m) / (constants::pi * fc * m);
        h[static_cast<std::size_t>(j)] = fc * sinc * bessel_i0(beta * std::sqrt(std::max(0.0, 1.0 - r * r))) / i0b;
    }
    return h;
}

}  // namespace

std::vector<DampedSinusoid> fit_damped_sinusoids(const std::vector<double>& samples, double dt, const PencilSettings& s) {
    using cd = std::complex<double>;
    if (!(dt > 0.0) || !(s.f_lo_hz > 0.0) || !(s.f_hi_hz > s.f_lo_hz) || !(s.f_hi_hz < 0.5 / dt))
        throw std::invalid_argument("fit_damped_sinusoids: need dt > 0 and 0 < f_lo < f_hi < the Nyquist frequency");
    if (s.max_components < 1 || !(s.relative_threshold > 0.0) || !(s.oversampling >= 1.0) || !(s.start_s >= 0.0))
        throw std::invalid_argument("fit_damped_sinusoids: bad settings (components, threshold, oversampling, start)");
    const auto first = static_cast<std::size_t>(std::ceil(s.start_s / dt - 1e-9));
    if (first >= samples.size()) throw std::invalid_argument("fit_damped_sinusoids: no samples after start_s");
    const std::size_t n = samples.size() - first;
    const double record = dt * static_cast<double>(n);
    const double centre = 0.5 * (s.f_lo_hz + s.f_hi_hz), half = 0.5 * (s.f_hi_hz - s.f_lo_hz);
    // The transition band: at least the half-width, and wide enough that the filter spans at most a quarter
    // of the record (its length is (A - 8) / (2.285 2 pi t dt) samples).
    const double a = std::max(s.stopband_db, 21.0);
    const double transition = std::max(half, 4.0 * (a - 8.0) / (2.285 * 2.0 * constants::pi * record));
    const std::vector<double> h = kaiser_low_pass(half + 0.5 * transition, transition, a, dt);
    const std::size_t taps = h.size();
    const double rate = s.oversampling * 2.0 * (half + transition);   // complex samples per second
    const std::size_t decimation = std::max<std::size_t>(1, static_cast<std::size_t>(1.0 / (dt * rate)));
    if (taps > n) throw std::invalid_argument("fit_damped_sinusoids: the record is shorter than the band's filter");
    const std::size_t k = (n - taps) / decimation + 1;
    if (k < 8) throw std::invalid_argument("fit_damped_sinusoids: fewer than 8 samples after decimation");

    // Mixed down by the band's centre, filtered where the filter lies on the signal, decimated.
    const double wc = 2.0 * constants::pi * centre * dt;
    std::vector<cd> mixed(n);
    for (std::size_t i = 0; i < n; ++i) mixed[i] = samples[first + i] * std::polar(1.0, -wc * static_cast<double>(i));
    Eigen::VectorXcd y(static_cast<Eigen::Index>(k));
    for (std::size_t q = 0; q < k; ++q) {
        cd sum = 0.0;
        const cd* x = mixed.data() + q * decimation;
        for (std::size_t j = 0; j < taps; ++j) sum += h[j] * x[j];
        y[static_cast<Eigen::Index>(q)] = sum;
    }

    // The pencil: Y = U S V^H, M poles from V's first M columns.
    const Eigen::Index kk = static_cast<Eigen::Index>(k), l = kk / 3;
    Eigen::MatrixXcd hankel(kk - l, l + 1);
    for (Eigen::Index r = 0; r < kk - l; ++r)
        for (Eigen::Index c = 0; c <= l; ++c) hankel(r, c) = y[r + c];
    const Eigen::BDCSVD<Eigen::MatrixXcd> svd(hankel, Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    if (!(sv[0] > 0.0)) return {};
    Eigen::Index m = 0;
    while (m < sv.size() && m < l && m < s.max_components && sv[m] > s.relative_threshold * sv[0]) ++m;
    const Eigen::MatrixXcd v = svd.matrixV().leftCols(m);
    const Eigen::MatrixXcd v1h = v.topRows(l).adjoint(), v2h = v.bottomRows(l).adjoint();
    const Eigen::MatrixXcd pencil = v2h * v1h.completeOrthogonalDecomposition().pseudoInverse();
    const Eigen::ComplexEigenSolver<Eigen::MatrixXcd> eig(pencil, false);
    const Eigen::VectorXcd poles = eig.eigenvalues();

    // Amplitudes: least squares on the Vandermonde matrix of the poles, then the filter divided out.
    Eigen::MatrixXcd vandermonde(kk, m);
    for (Eigen::Index i = 0; i < m; ++i) {
        cd p = 1.0;
        for (Eigen::Index q = 0; q < kk; ++q) vandermonde(q, i) = p, p *= poles[i];
    }
    const Eigen::VectorXcd b = vandermonde.colPivHouseholderQr().solve(y);
    const double step = dt * static_cast<double>(decimation);
    std::vector<DampedSinusoid> out;
    for (Eigen::Index i = 0; i < m; ++i) {
        DampedSinusoid c;
        c.frequency_hz = centre + std::arg(poles[i]) / (2.0 * constants::pi * step);
        c.damping_per_s = -std::log(std::abs(poles[i])) / step;
        if (c.frequency_hz < s.f_lo_hz || c.frequency_hz > s.f_hi_hz) continue;
        const cd z = std::exp(cd(-c.damping_per_s, 2.0 * constants::pi * (c.frequency_hz - centre)) * dt);
        cd gain = 0.0, zj = 1.0;
        for (std::size_t j = 0; j < taps; ++j) gain += h[j] * zj, zj *= z;
        const cd amplitude = b[i] / gain;
        c.amplitude = 2.0 * std::abs(amplitude);
        c.phase_rad = std::arg(amplitude);
        out.push_back(c);
    }
    std::sort(out.begin(), out.end(), [](const DampedSinusoid& p, const DampedSinusoid& q) { return p.frequency_hz < q.frequency_hz; });
    return out;
}

double record_energy(const DampedSinusoid& c, double record_s) {
    const double x = 2.0 * c.damping_per_s * record_s;
    const double duration = std::abs(x) < 1e-12 ? record_s : -std::expm1(-x) / (2.0 * c.damping_per_s);
    return 0.5 * c.amplitude * c.amplitude * duration;
}

double energy_weighted_frequency(const std::vector<DampedSinusoid>& components, double record_s) {
    double sum = 0.0, weighted = 0.0;
    for (const DampedSinusoid& c : components) {
        const double e = record_energy(c, record_s);
        sum += e;
        weighted += e * c.frequency_hz;
    }
    return sum > 0.0 ? weighted / sum : 0.0;
}

}  // namespace ameoto::reference
