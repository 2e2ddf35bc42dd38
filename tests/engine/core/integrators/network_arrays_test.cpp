// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/network_arrays: forces, energy and the assembled K, C agree.
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/integrators/network_arrays.hpp"
#include "engine/core/random.hpp"

namespace {

ameoto::NetworkArrays random_network(int n, int links, ameoto::Random& rng) {
    ameoto::NetworkArrays a;
    for (int i = 0; i < n; ++i) {
        const double m = 1e-3 * (0.5 + rng.uniform());
        a.mass_kg.push_back(m);
        a.inverse_mass.push_back(1.0 / m);
        a.ground_damping.push_back(rng.uniform() < 0.5 ? 0.0 : 0.01 * rng.uniform());
        a.anchor_stiffness.push_back(rng.uniform() < 0.7 ? 0.0 : 1000.0 * rng.uniform());
    }
    for (int l = 0; l < links; ++l) {
        const int i = static_cast<int>(rng.uniform() * n) % n;
        const int j = (i + 1 + static_cast<int>(rng.uniform() * (n - 1))) % n;
        a.link_a.push_back(i);
        a.link_b.push_back(j);
        a.link_stiffness.push_back(500.0 * (0.1 + rng.uniform()));
        a.link_damping.push_back(0.02 * rng.uniform());
    }
    return a;
}

}  // namespace

TEST_CASE("network_arrays: forces are ext - K x - C v with the assembled K and C") {
    ameoto::Random rng(5);
    const auto a = random_network(12, 30, rng);
    const Eigen::MatrixXd k = Eigen::MatrixXd(a.stiffness_matrix()), c = Eigen::MatrixXd(a.damping_matrix());
    Eigen::VectorXd x(12), v(12), ext(12), f(12);
    for (int i = 0; i < 12; ++i) {
        x[i] = rng.uniform() - 0.5;
        v[i] = rng.uniform() - 0.5;
        ext[i] = rng.uniform() - 0.5;
    }
    const Eigen::VectorXd expected = ext - k * x - c * v;
    a.forces(x.data(), v.data(), ext.data(), f.data());
    // network_arrays.hpp: the same sum in a different order, rounding only (1e-12 of the largest term).
    const double scale = (k.cwiseAbs() * x.cwiseAbs()).maxCoeff() + (c.cwiseAbs() * v.cwiseAbs()).maxCoeff() + 1.0;
    CHECK((f - expected).cwiseAbs().maxCoeff() <= 1e-12 * scale);
    // Without damping / without external force.
    a.forces(x.data(), nullptr, ext.data(), f.data());
    CHECK((f - (ext - k * x)).cwiseAbs().maxCoeff() <= 1e-12 * scale);
    a.forces(x.data(), v.data(), nullptr, f.data());
    CHECK((f - (-k * x - c * v)).cwiseAbs().maxCoeff() <= 1e-12 * scale);
    a.forces(x.data(), nullptr, nullptr, f.data());
    CHECK((f - (-k * x)).cwiseAbs().maxCoeff() <= 1e-12 * scale);
    // K and C symmetric; links' columns sum to zero, so 1'K = anchors (network_arrays.hpp).
    CHECK((k - k.transpose()).cwiseAbs().maxCoeff() == 0.0);
    for (int i = 0; i < 12; ++i) CHECK(k.col(i).sum() == doctest::Approx(a.anchor_stiffness[static_cast<std::size_t>(i)]).epsilon(1e-12).scale(1000.0));
    // Energy: 1/2 v'Mv + 1/2 x'Kx (rounding).
    double kinetic = 0.0;
    for (int i = 0; i < 12; ++i) kinetic += 0.5 * a.mass_kg[static_cast<std::size_t>(i)] * v[i] * v[i];
    CHECK(a.energy(x.data(), v.data()) == ameoto::test::relative(kinetic + 0.5 * x.dot(k * x)).epsilon(1e-12));
    CHECK(a.energy(x.data(), nullptr) == ameoto::test::relative(0.5 * x.dot(k * x)).epsilon(1e-12));
}
