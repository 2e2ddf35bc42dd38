// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/modal_decomposition: normal modes, Rayleigh damping, lowest modes of large bodies.
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>

#include <Eigen/Dense>

#include "engine/core/modal_decomposition.hpp"
#include "tests/engine/core/integrators/test_bodies.hpp"

using namespace ameoto;
using namespace ameoto::test;

TEST_CASE("modal_decomposition: mass-normalised modes of K phi = omega^2 M phi") {
    auto body = lattice_membrane(40, 0.06, 1000.0, 20.0, 2e-6);
    const auto& a = body.network.arrays();
    const auto d = decompose_modes(a);
    const auto n = static_cast<Eigen::Index>(a.mass_count());
    REQUIRE(d.omega.size() == n);
    Eigen::VectorXd m(n);
    for (Eigen::Index i = 0; i < n; ++i) m[i] = a.mass(static_cast<std::size_t>(i));
    const Eigen::MatrixXd k = Eigen::MatrixXd(a.stiffness_matrix());
    // modal_decomposition.hpp: Phi' M Phi = I, K Phi = M Phi Omega^2 (rounding: 1e-10 relative).
    CHECK((d.shapes.transpose() * m.asDiagonal() * d.shapes - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff() < 1e-10);
    const Eigen::MatrixXd residual = k * d.shapes - m.asDiagonal() * d.shapes * d.omega.cwiseAbs2().asDiagonal();
    CHECK(residual.cwiseAbs().maxCoeff() < 1e-10 * (k.cwiseAbs() * d.shapes.cwiseAbs()).maxCoeff());
    for (Eigen::Index j = 1; j < n; ++j) CHECK(d.omega[j] >= d.omega[j - 1]);
    // Momentum weights: sum_k w_k^2 = 1'M Phi Phi' M 1 = 1'M 1 (Phi Phi' = M^-1), the total mass.
    CHECK(d.net_force_weight.squaredNorm() == ameoto::test::relative(m.sum()).epsilon(1e-10));
    // Rayleigh damping (membrane.hpp, alpha 20 /s, beta 2e-6 s) is read back from the elements and is
    // diagonal in the modes: s_k = (alpha + beta omega_k^2) / 2.
    const auto r = rayleigh_damping(a);
    CHECK(r.exact);
    CHECK(r.alpha == doctest::Approx(20.0).epsilon(1e-9));
    CHECK(r.beta == ameoto::test::relative(2e-6).epsilon(1e-9));
    CHECK(d.non_proportionality < 1e-9);
    for (Eigen::Index j = 0; j < n; ++j)
        CHECK(d.damping_rate[j] == doctest::Approx(0.5 * (20.0 + 2e-6 * d.omega[j] * d.omega[j])).epsilon(1e-9));
}

TEST_CASE("modal_decomposition: non-proportional damping is reported, not hidden") {
    auto body = lattice_membrane(20);
    TransverseNetwork net = body.network;
    net.add_anchor(4, 0.0, 0.5);   // one extra damper at one mass: C is no longer alpha M + beta K
    const auto r = rayleigh_damping(net.arrays());
    CHECK_FALSE(r.exact);
    const auto d = decompose_modes(net.arrays());
    CHECK(d.non_proportionality > 0.01);   // the modes are coupled by C; modal damping keeps the diagonal
}

TEST_CASE("modal_decomposition: lowest_modes agrees with the dense solve, free bodies included") {
    auto body = lattice_membrane(60);
    const auto dense = decompose_modes(body.network.arrays());
    const auto low = lowest_modes(body.network.arrays(), 6);
    REQUIRE(low.omega.size() == 6);
    for (int k = 0; k < 6; ++k) CHECK(low.omega[k] == doctest::Approx(dense.omega[k]).epsilon(1e-10));   // both converge to rounding
    CHECK(low.iterations > 1);

    auto chain = free_chain();
    const auto free_low = lowest_modes(chain.arrays(), 2);
    const auto free_dense = decompose_modes(chain.arrays());
    CHECK(free_dense.omega[0] < 1e-6 * free_dense.omega[1]);   // the rigid mode (rounding)
    CHECK(free_low.omega[0] < 1e-6 * free_low.omega[1]);
    CHECK(free_low.omega[1] == doctest::Approx(free_dense.omega[1]).epsilon(1e-10));
}
