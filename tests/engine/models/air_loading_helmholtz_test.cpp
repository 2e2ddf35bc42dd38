// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/air_loading_helmholtz: the umbrella's air mass with the air compressible.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include <Eigen/Eigenvalues>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/air_loading_helmholtz.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/membrane.hpp"

using ameoto::Point2;

namespace {

constexpr double kHelmPi = ameoto::constants::pi;
constexpr double kHelmRho = ameoto::constants::air_density;
constexpr double kHelmC = ameoto::constants::speed_of_sound_air;

// integral of 1 / |x - y| over the polygon by a fine midpoint rule on its bounding box (for the test).
double brute_inverse_distance(Point2 x, double x0, double x1, double y0, double y1, int n) {
    double sum = 0.0;
    const double hx = (x1 - x0) / n, hy = (y1 - y0) / n;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double px = x0 + (i + 0.5) * hx, py = y0 + (j + 0.5) * hy;
            sum += hx * hy / std::hypot(px - x.x, py - x.y);
        }
    return sum;
}

}  // namespace

TEST_CASE("air loading (Helmholtz): the kernel's remainder and the polygon's 1/r integral") {
    // The remainder's series and its closed form meet at kr = 0.05, and it is -i k^3 / (12 pi) at r = 0.
    const double k = 20.0;
    const std::complex<double> below = ameoto::helmholtz_kernel_remainder(k, 0.0499 / k), above = ameoto::helmholtz_kernel_remainder(k, 0.0501 / k);
    CHECK(std::abs(below - above) < 1e-3 * std::abs(below));
    const std::complex<double> at0 = ameoto::helmholtz_kernel_remainder(k, 0.0);
    CHECK(std::abs(at0.real()) < 1e-12 * k * k * k);
    CHECK(std::abs(at0.imag() / (-k * k * k / (12.0 * kHelmPi)) - 1.0) < 1e-12);
    // A closed form far from 0: (e^(-ix)(1 + ix) - 1 - x^2 / 2) / (4 pi r^3) at x = 2.
    const double r = 2.0 / k;
    const std::complex<double> e = std::exp(std::complex<double>(0.0, -2.0)) * std::complex<double>(1.0, 2.0) - 1.0 - 2.0;
    CHECK(std::abs(ameoto::helmholtz_kernel_remainder(k, r) - e / (4.0 * kHelmPi * r * r * r)) < 1e-12 * std::abs(e / (r * r * r)));

    // The unit square from its centre: 4 ln(1 + sqrt 2); from its corner: 2 asinh(1); either sense.
    const std::vector<Point2> square{{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
    const std::vector<Point2> clockwise{{0.0, 0.0}, {0.0, 1.0}, {1.0, 1.0}, {1.0, 0.0}};
    CHECK(ameoto::polygon_inverse_distance_integral({0.5, 0.5}, square) == doctest::Approx(4.0 * std::log(1.0 + std::sqrt(2.0))).epsilon(1e-12));
    CHECK(ameoto::polygon_inverse_distance_integral({0.5, 0.5}, clockwise) == doctest::Approx(4.0 * std::log(1.0 + std::sqrt(2.0))).epsilon(1e-12));
    CHECK(ameoto::polygon_inverse_distance_integral({0.0, 0.0}, square) == doctest::Approx(2.0 * std::asinh(1.0)).epsilon(1e-12));
    // A point outside, and one inside off centre, against a fine midpoint sum.
    CHECK(ameoto::polygon_inverse_distance_integral({1.7, -0.4}, square) == doctest::Approx(brute_inverse_distance({1.7, -0.4}, 0, 1, 0, 1, 800)).epsilon(1e-4));
    CHECK(ameoto::polygon_inverse_distance_integral({0.3, 0.8}, square) == doctest::Approx(brute_inverse_distance({0.3, 0.8}, 0, 1, 0, 1, 1000)).epsilon(2e-3));
    // A triangle (the apex sub-cell's shape) from outside.
    const std::vector<Point2> triangle{{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
    double brute = 0.0;
    for (int i = 0; i < 1000; ++i)
        for (int j = 0; j < 1000; ++j) {
            const double px = (i + 0.5) / 1000.0, py = (j + 0.5) / 1000.0;
            if (px + py < 1.0) brute += 1e-6 / std::hypot(px - 1.0, py - 1.0);
        }
    CHECK(ameoto::polygon_inverse_distance_integral({1.0, 1.0}, triangle) == doctest::Approx(brute).epsilon(1e-3));
}

TEST_CASE("air loading (Helmholtz): the umbrella's air mass tends to the incompressible one, and its rigid motion radiates as a dipole") {
    const ameoto::Canopy canopy({}, ameoto::MembraneMaterial::nylon_canopy(), 1.0 / 48000.0);
    const int n = canopy.panel_count() * canopy.nodes_per_panel();
    const ameoto::AddedMass incompressible = ameoto::canopy_added_mass(canopy, kHelmRho);

    // omega -> 0: the incompressible M_a (the same sampling and extrapolation; the kernel's difference is
    // O(k^2)). At 0.01 Hz k^2 a^2 is 2e-10.
    const auto t0 = std::chrono::steady_clock::now();
    const ameoto::CanopyAirImpedance slow = ameoto::canopy_air_mass_at(canopy, kHelmRho, kHelmC, 2.0 * kHelmPi * 0.01);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Eigen::MatrixXcd m0 = slow.matrix();
    REQUIRE(m0.rows() == n);
    const double scale = incompressible.matrix.norm();
    CHECK((m0.real() - incompressible.matrix).norm() < 1e-7 * scale);
    CHECK(m0.imag().norm() < 1e-7 * scale);
    std::printf("air mass at one frequency (Helmholtz): %.2f s wall\n", took);

    // Rigid motion at small ka: the mass is the incompressible one, and the resistance -omega Im(1' M_a 1)
    // is a point force's dipole radiation, R = k^2 omega^2 m^2 / (12 pi rho0 c) for the force omega m v
    // (Dowling & Ffowcs Williams 1983, s. 2.6: W = k^2 F^2 / (24 pi rho0 c)); the next order is (ka)^2.
    // Richardson's step is static (the header), so the resistance is the finer level's: its m is the finer
    // level's rigid mass (+1.9 % over the extrapolated one, whose dipole power is 3.9 % lower).
    const Eigen::VectorXcd ones = Eigen::VectorXcd::Ones(n);
    const double mass0 = incompressible.matrix.sum();
    const double finer_mass = ameoto::canopy_added_mass(canopy, kHelmRho, ameoto::CanopyAirMassOptions{24, false}).matrix.sum();
    const double radius = canopy.geometry().radius_m;
    const ameoto::CanopyAirImpedanceBuilder builder(canopy, kHelmRho, kHelmC);
    for (const double ka : {0.1, 0.2, 0.4}) {
        const double k = ka / radius, omega = k * kHelmC;
        const std::complex<double> rigid = ones.dot(builder.at(omega).matrix() * ones);
        const double resistance = -omega * rigid.imag();
        const double dipole = k * k * omega * omega * finer_mass * finer_mass / (12.0 * kHelmPi * kHelmRho * kHelmC);
        std::printf("  rigid canopy at ka %.1f: mass %+.3f %% of the incompressible, resistance %.4g against the dipole's %.4g kg/s (%+.2f %%)\n", ka,
                    100.0 * (rigid.real() / mass0 - 1.0), resistance, dipole, 100.0 * (resistance / dipole - 1.0));
        CHECK(std::abs(rigid.real() / mass0 - 1.0) < 0.005 + 0.25 * ka * ka);   // measured +0.19, +0.74, +3.0 %
        CHECK(std::abs(resistance / dipole - 1.0) < 0.01 + 0.5 * ka * ka);     // the (ka)^2 order: +4.6 % at ka 0.4
    }
}

TEST_CASE("air loading (Helmholtz): at 2 kHz the umbrella is passive and its short waves carry more air") {
    const ameoto::Canopy canopy({}, ameoto::MembraneMaterial::nylon_canopy(), 1.0 / 48000.0);
    const double omega = 2.0 * kHelmPi * 2000.0;
    const ameoto::CanopyAirImpedance z = ameoto::canopy_air_mass_at(canopy, kHelmRho, kHelmC, omega);
    const Eigen::MatrixXcd m = z.matrix();
    // Complex symmetric (reciprocity), and -Im M_a, the radiation resistance over omega, positive
    // semi-definite: no motion draws power from the air.
    CHECK((m - m.transpose()).norm() < 1e-12 * m.norm());
    const Eigen::MatrixXd resistance = -m.imag();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (resistance + resistance.transpose()));
    std::printf("at 2 kHz: -Im M_a's eigenvalues %.3g .. %.3g kg\n", eig.eigenvalues().minCoeff(), eig.eigenvalues().maxCoeff());
    CHECK(eig.eigenvalues().minCoeff() > -1e-3 * eig.eigenvalues().maxCoeff());   // -1e-4 here: the sampling's
    // Short waves (10 cm, kappa = 63 /m against k = 37 /m): on an infinite screen the air's mass per area
    // grows by 1 / sqrt(1 - (k / kappa)^2) = 1.23 over the incompressible (measured on panel 0: 1.243; the
    // panel's edges spread the wave's wavenumbers, some nearer k, where the mass grows without bound).
    const ameoto::AddedMass incompressible = ameoto::canopy_added_mass(canopy, kHelmRho);
    Eigen::VectorXd wave = Eigen::VectorXd::Zero(m.rows());
    for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
        wave[i] = std::cos(2.0 * kHelmPi * canopy.rest_position(0, i).x / 0.1);   // 10 cm waves along x on panel 0
    }
    const double compressible_mass = wave.dot(m.real() * wave), plain = wave.dot(incompressible.matrix * wave);
    std::printf("  10 cm waves on panel 0: air mass %+.2f %% of the incompressible\n", 100.0 * (compressible_mass / plain - 1.0));
    CHECK(compressible_mass > 1.18 * plain);
    CHECK(compressible_mass < 1.35 * plain);
}
