// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/modal: exact two-pole resonators per mode.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

namespace {

// The continuous impulse response of a damped oscillator m x'' + z x' + k x = J delta(t):
// x(t) = (J / m) e^{-s t} sin(wd t) / wd (cosh/sinh when overdamped), s = z / 2m.
double continuous_response(double m, double k, double z, double j, double t) {
    const double s = z / (2.0 * m), d = k / m - s * s;
    if (d > 1e-9 * (k / m)) return j / m * std::exp(-s * t) * std::sin(std::sqrt(d) * t) / std::sqrt(d);
    if (d < -1e-9 * (k / m)) return j / m * std::exp(-s * t) * std::sinh(std::sqrt(-d) * t) / std::sqrt(-d);
    return j / m * std::exp(-s * t) * t;
}

// Independent modes of a network: the generalised eigenproblem on dense K and M built here.
Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> independent_modes(const NetworkArrays& a) {
    const auto n = static_cast<Eigen::Index>(a.mass_count());
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n), m = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
        m(i, i) = a.mass_kg[static_cast<std::size_t>(i)];
        k(i, i) += a.anchor_stiffness[static_cast<std::size_t>(i)];
    }
    for (std::size_t l = 0; l < a.link_count(); ++l) {
        const Eigen::Index i = a.link_a[l], j = a.link_b[l];
        k(i, i) += a.link_stiffness[l];
        k(j, j) += a.link_stiffness[l];
        k(i, j) -= a.link_stiffness[l];
        k(j, i) -= a.link_stiffness[l];
    }
    return Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(k, m);
}

}  // namespace

TEST_CASE("modal: one oscillator's samples are the continuous impulse response, at any T") {
    const double m = 1e-3, omega0 = 2.0 * kPi * 1000.0;
    struct Case {
        double omega_t, z;
    };
    // Underdamped below and above Nyquist (omega T = pi), critically damped, overdamped, free mass.
    for (const Case c : {Case{0.3, 0.0}, Case{0.3, 0.5}, Case{2.5, 0.2}, Case{7.0, 0.1}, Case{1.0, 2.0 * m * omega0},
                         Case{1.0, 10.0 * m * omega0}, Case{0.0, 0.0}, Case{0.0, 0.3}}) {
        CAPTURE(c.omega_t);
        CAPTURE(c.z);
        const double t = c.omega_t > 0.0 ? c.omega_t / omega0 : kT;
        const double k = c.omega_t > 0.0 ? m * omega0 * omega0 : 0.0;
        TransverseNetwork net;
        net.add_mass(m, c.z);
        if (k > 0.0) net.add_anchor(0, k, 0.0);
        net.finalize(t, options_for(Integrator::modal));
        REQUIRE(net.modal().mode_count() == 1);
        net.apply_force(0, 2.0);
        double worst = 0.0, peak = 0.0;
        for (int n = 0; n < 400; ++n) {
            net.step();
            // modal.hpp: the impulse T f at the step's start; x after step n is x((n+1) T).
            const double exact = continuous_response(m, k, c.z, 2.0 * t, (n + 1) * t);
            worst = std::max(worst, std::abs(net.position(0) - exact));
            peak = std::max(peak, std::abs(exact));
        }
        // Exact to rounding: 1e-12 of the response's peak over 400 samples.
        CHECK(worst <= 1e-12 * peak);
    }
}

TEST_CASE("modal: positions obey the two-pole recursion q[n] = a1 q[n-1] + a2 q[n-2] + g p[n]") {
    const double m = 1e-3, omega0 = 2.0 * kPi * 3000.0, z = 0.4;
    auto net = one_oscillator(m, omega0, z);
    net.finalize(kT, options_for(Integrator::modal));
    const Resonator r = net.modal().resonator(0);
    const double s = z / (2.0 * m), wd = std::sqrt(omega0 * omega0 - s * s);
    // physics.md s.3: a1 = 2 e^{-sT} cos(wd T), a2 = -e^{-2sT}; modal.hpp: g = T e^{-sT} sin(wd T) / wd.
    CHECK(r.a1 == ameoto::test::relative(2.0 * std::exp(-s * kT) * std::cos(wd * kT)).epsilon(1e-13));
    CHECK(r.a2 == ameoto::test::relative(-std::exp(-2.0 * s * kT)).epsilon(1e-13));
    CHECK(r.g == ameoto::test::relative(kT * std::exp(-s * kT) * std::sin(wd * kT) / wd).epsilon(1e-13));
    // The recorded positions, with forces at arbitrary steps: x = q / sqrt(m), p = f / sqrt(m).
    std::vector<double> q, p;
    for (int n = 0; n < 200; ++n) {
        const double f = (n % 17 == 0 || n == 5) ? 0.3 * (1 + n % 3) : 0.0;
        net.apply_force(0, f);
        net.step();
        q.push_back(net.position(0) * std::sqrt(m));
        p.push_back(f / std::sqrt(m));
    }
    double worst = 0.0, scale = 0.0;
    for (std::size_t n = 2; n < q.size(); ++n) {
        worst = std::max(worst, std::abs(q[n] - (r.a1 * q[n - 1] + r.a2 * q[n - 2] + r.g * p[n])));
        scale = std::max(scale, std::abs(q[n]));
    }
    CHECK(worst <= 1e-13 * scale);   // rounding only
}

TEST_CASE("modal: at large T every mode rings at its eigenfrequency and the response is exact") {
    auto body = lattice_membrane(30);
    const auto modes = independent_modes(body.network.arrays());
    const Eigen::VectorXd omega = modes.eigenvalues().cwiseSqrt();
    const double t = 2.5 / omega.maxCoeff();   // omega_max T = 2.5: the explicit scheme would diverge
    body.network.finalize(t, options_for(Integrator::modal));
    const auto& modal = body.network.modal();
    const int n = body.network.mass_count();
    REQUIRE(modal.mode_count() == n);
    // Each mode alone (force M phi_k makes p = e_k): the samples are a sinusoid whose
    // (y[n+1] + y[n-1]) / (2 y[n]) is cos(omega T) exactly; read omega back from it.
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
        body.network.reset();
        const auto phi = modes.eigenvectors().col(k);
        for (int i = 0; i < n; ++i) body.network.apply_force(i, body.network.mass(i) * phi[i]);
        int pick = 0;
        phi.cwiseAbs().maxCoeff(&pick);
        std::vector<double> y;
        for (int s = 0; s < 64; ++s) {
            body.network.step();
            y.push_back(body.network.position(pick));
        }
        double num = 0.0, den = 0.0;
        for (std::size_t s = 1; s + 1 < y.size(); ++s) {
            num += (y[s + 1] + y[s - 1]) * y[s];
            den += 2.0 * y[s] * y[s];
        }
        const double measured = std::acos(num / den) / t;
        worst = std::max(worst, std::abs(measured / omega[k] - 1.0));
    }
    // modal.hpp: exact frequency for every mode; 1e-9 relative (acos near 0 and pi loses digits).
    CHECK(worst < 1e-9);

    // The whole impulse response at a pickup node vs the continuous sum over modes:
    // x_o(t) = J sum_k phi_ok phi_hk sin(omega_k t) / omega_k.
    body.network.reset();
    const int hit = 3, obs = n - 2;
    body.network.apply_force(hit, 1.0);
    double err = 0.0, peak = 0.0;
    for (int s = 0; s < 300; ++s) {
        body.network.step();
        const double time = (s + 1) * t;
        double exact = 0.0;
        for (int k = 0; k < n; ++k)
            exact += t * modes.eigenvectors()(obs, k) * modes.eigenvectors()(hit, k) * std::sin(omega[k] * time) / omega[k];
        err = std::max(err, std::abs(body.network.position(obs) - exact));
        peak = std::max(peak, std::abs(exact));
    }
    CHECK(err <= 1e-10 * peak);   // two independent eigen-solves agree to ~1e-12; 1e-10 of the peak
}

TEST_CASE("modal: modes are selected by frequency, count and net-force weight") {
    auto body = lattice_membrane(30, 0.06, 1000.0, 20.0, 2e-6);
    const auto all = decompose_modes(body.network.arrays());
    const double f_cut = 0.5 * (all.omega[10] + all.omega[11]) / (2.0 * kPi);
    {
        NetworkOptions o = options_for(Integrator::modal);
        o.modal.max_frequency_hz = f_cut;
        TransverseNetwork net = lattice_membrane(30, 0.06, 1000.0, 20.0, 2e-6).network;
        net.finalize(kT, o);
        CHECK(net.modal().mode_count() == 11);   // modes 0..10 lie below the cut
        for (int k = 0; k < net.modal().mode_count(); ++k) CHECK(net.modal().mode_omega(k) / (2.0 * kPi) <= f_cut);
        // Rayleigh damping: s_k = (alpha + beta omega_k^2) / 2 (membrane.hpp), rounding only.
        for (int k = 0; k < net.modal().mode_count(); ++k)
            CHECK(net.modal().mode_damping_rate(k) == doctest::Approx(0.5 * (20.0 + 2e-6 * std::pow(net.modal().mode_omega(k), 2))).epsilon(1e-9));
    }
    {
        NetworkOptions o = options_for(Integrator::modal);
        o.modal.max_modes = 5;
        TransverseNetwork net = lattice_membrane(30).network;
        net.finalize(kT, o);
        REQUIRE(net.modal().mode_count() == 5);
        for (int k = 0; k < 5; ++k) CHECK(net.modal().mode_omega(k) == doctest::Approx(all.omega[k]).epsilon(1e-9));
    }
    {
        NetworkOptions o = options_for(Integrator::modal);
        o.modal.min_net_force_weight = 0.05;
        TransverseNetwork net = lattice_membrane(30).network;
        net.finalize(kT, o);
        const double w_max = all.net_force_weight.cwiseAbs().maxCoeff();
        int expected = 0;
        for (Eigen::Index k = 0; k < all.omega.size(); ++k) expected += std::abs(all.net_force_weight[k]) >= 0.05 * w_max;
        CHECK(net.modal().mode_count() == expected);
        CHECK(expected < net.mass_count());
    }
}
