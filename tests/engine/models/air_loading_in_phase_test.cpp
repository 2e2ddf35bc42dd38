// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/air_loading_in_phase: the in-phase block of the compressible air mass by the
// kernel's series, held to CanopyAirImpedanceBuilder's direct quadrature (the exponential itself).
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading_helmholtz.hpp"
#include "engine/models/air_loading_in_phase.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/membrane.hpp"

namespace {

constexpr double kInPhaseRho = ameoto::constants::air_density;
constexpr double kInPhaseC = ameoto::constants::speed_of_sound_air;

}  // namespace

TEST_CASE("in-phase air mass: the series is the builder's block m = 0 to its truncation, passive, and zero at rest") {
    const ameoto::Canopy canopy({}, ameoto::MembraneMaterial::nylon_canopy(), 1.0 / 48000.0);
    const int nodes = canopy.nodes_per_panel(), panels = canopy.panel_count();
    // ka = 2 on the 0.5 m canopy (the server's default limit, air_canopy.hpp): 218 Hz.
    const double max_omega = 2.0 * kInPhaseC / canopy.geometry().radius_m;
    const ameoto::InPhaseAirMass series(canopy, kInPhaseRho, kInPhaseC, max_omega);
    MESSAGE("terms to k r = " << 2.0 * max_omega / kInPhaseC * canopy.geometry().radius_m << ": " << series.terms());
    CHECK(series.terms() >= 20);
    CHECK(series.terms() <= 40);
    const ameoto::CanopyAirImpedanceBuilder builder(canopy, kInPhaseRho, kInPhaseC);
    const ameoto::CanopyAirImpedance at_rest = builder.at(0.0);
    CHECK(series.change_at(0.0).norm() == 0.0);
    const Eigen::VectorXcd uniform = Eigen::VectorXcd::Ones(nodes);
    for (const double hz : {40.0, 120.0, max_omega / (2.0 * ameoto::constants::pi)}) {
        const double omega = 2.0 * ameoto::constants::pi * hz;
        const Eigen::MatrixXcd d = series.change_at(omega);
        const Eigen::MatrixXcd direct = builder.at(omega).fourier[0] - at_rest.fourier[0];
        const double error = (d - direct).norm() / direct.norm();
        // The canopy moving as one (every node up): more mass as the frequency rises, and a radiation
        // resistance -omega Im >= 0.
        const std::complex<double> rigid = static_cast<double>(panels) * (uniform.transpose() * d * uniform)(0, 0);
        MESSAGE(hz << " Hz: |series - direct| / |direct| = " << error << "; the rigid canopy's extra mass " << rigid.real()
                   << " kg, radiation resistance " << -omega * rigid.imag() << " kg/s");
        CHECK(error < 1e-9);
        CHECK(rigid.real() > 0.0);
        CHECK(rigid.imag() < 0.0);
        CHECK((d - d.transpose()).norm() <= 1e-15 * d.norm());
    }
    // Continued to complex frequencies the series is analytic (a polynomial in k under the solve): its
    // derivative along the imaginary axis is the one along the real axis (Cauchy-Riemann), to the finite
    // differences' O(h).
    const double w = 2.0 * ameoto::constants::pi * 150.0, h = 1e-3 * w;
    const Eigen::MatrixXcd at_w = series.change_at(w);
    const Eigen::MatrixXcd along_real = (series.change_at(w + h) - series.change_at(w - h)) / (2.0 * h);
    const Eigen::MatrixXcd along_imaginary =
        (series.change_at(std::complex<double>(w, h)) - series.change_at(std::complex<double>(w, -h))) / std::complex<double>(0.0, 2.0 * h);
    CHECK((series.change_at(std::complex<double>(w, 0.0)) - at_w).norm() == 0.0);
    CHECK((along_real - along_imaginary).norm() < 1e-5 * along_real.norm());
    CHECK_THROWS_AS(series.change_at(max_omega * 1.001), std::invalid_argument);
    CHECK_THROWS_AS(series.change_at(std::complex<double>(max_omega, 0.1 * max_omega)), std::invalid_argument);
    CHECK_THROWS_AS(series.change_at(-1.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::InPhaseAirMass(canopy, 0.0, kInPhaseC, 100.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::InPhaseAirMass(canopy, kInPhaseRho, kInPhaseC, -1.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::InPhaseAirMass(canopy, kInPhaseRho, kInPhaseC, 100.0, {.rows = 5}), std::invalid_argument);
}
