// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/core/integrators/sparse_ldlt: the factor-once, solve-without-allocating LDLT.
#include <doctest/doctest.h>

#include <stdexcept>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "engine/core/integrators/sparse_ldlt.hpp"
#include "engine/core/random.hpp"
#include "tests/support/rt_probe_scope.hpp"

namespace {

// An SPD matrix with a lattice-like sparsity: diagonal dominance from a 2-D grid Laplacian plus a mass.
Eigen::SparseMatrix<double> grid_matrix(int nx, int ny, ameoto::Random& rng) {
    const int n = nx * ny;
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const int a = j * nx + i;
            t.emplace_back(a, a, 0.1 + rng.uniform());
            for (int b : {i + 1 < nx ? a + 1 : -1, j + 1 < ny ? a + nx : -1}) {
                if (b < 0) continue;
                const double k = 1.0 + rng.uniform();
                t.emplace_back(a, a, k);
                t.emplace_back(b, b, k);
                t.emplace_back(a, b, -k);
                t.emplace_back(b, a, -k);
            }
        }
    }
    Eigen::SparseMatrix<double> m(n, n);
    m.setFromTriplets(t.begin(), t.end());
    return m;
}

}  // namespace

TEST_CASE("sparse_ldlt: solves match a dense solve, in place or not, without allocating") {
    ameoto::Random rng(3);
    const auto a = grid_matrix(9, 7, rng);
    ameoto::SparseLdlt s;
    s.factor(a);
    CHECK(s.size() == 63);
    CHECK(s.factor_nonzeros() > 0);
    Eigen::VectorXd b(63), x(63);
    for (int i = 0; i < 63; ++i) b[i] = rng.uniform() - 0.5;
    const Eigen::VectorXd expected = Eigen::MatrixXd(a).ldlt().solve(b);
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        s.solve(b.data(), x.data());
    }
    CHECK(audit.entries() > 0);
    CHECK(audit.violations() == 0);   // sparse_ldlt.hpp: the solve never allocates
    // Backward stable solve of a well-conditioned system: 1e-12 relative.
    CHECK((x - expected).norm() <= 1e-12 * expected.norm());
    CHECK((a * x - b).norm() <= 1e-12 * b.norm());
    Eigen::VectorXd y = b;
    s.solve(y.data(), y.data());   // in place
    CHECK((y - x).norm() <= 1e-14 * x.norm());
}

TEST_CASE("sparse_ldlt: Eigen's own solve allocates (why sparse_ldlt.hpp has its own)") {
    ameoto::Random rng(4);
    const auto a = grid_matrix(6, 6, rng);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
    Eigen::VectorXd b = Eigen::VectorXd::Ones(36), x(36);
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        x = ldlt.solve(b);
    }
    // Documents the finding in sparse_ldlt.hpp (Eigen 3.4: 2 allocations per solve). A warning, not a
    // failure: if a future Eigen stops allocating, this says so and sparse_ldlt could be retired.
    WARN(audit.violations() > 0);
    CHECK((a * x - b).norm() <= 1e-12 * b.norm());
}

TEST_CASE("sparse_ldlt: refuses matrices that are not positive definite") {
    Eigen::SparseMatrix<double> m(2, 2);
    m.insert(0, 0) = 1.0;
    m.insert(1, 1) = -1.0;
    ameoto::SparseLdlt s;
    CHECK_THROWS_AS(s.factor(m), std::invalid_argument);
    Eigen::SparseMatrix<double> r(2, 3);
    CHECK_THROWS_AS(s.factor(r), std::invalid_argument);
}
