// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/sparse_ldlt.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/SparseCholesky>

namespace ameoto {

void SparseLdlt::factor(const Eigen::SparseMatrix<double>& a) {
    if (a.rows() != a.cols()) throw std::invalid_argument("SparseLdlt: matrix must be square");
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(a);
    if (ldlt.info() != Eigen::Success) throw std::invalid_argument("SparseLdlt: factorisation failed");
    const auto n = static_cast<std::size_t>(a.rows());
    const Eigen::VectorXd d = ldlt.vectorD();
    for (Eigen::Index i = 0; i < d.size(); ++i)
        if (!(d[i] > 0.0) || !std::isfinite(d[i])) throw std::invalid_argument("SparseLdlt: matrix is not positive definite");
    diagonal_.assign(d.data(), d.data() + d.size());

    // The permutation as an index map, found by applying P to 0..n-1 (no reliance on Eigen's convention).
    Eigen::VectorXd index(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) index[static_cast<Eigen::Index>(i)] = static_cast<double>(i);
    permutation_.resize(n);
    if (ldlt.permutationP().size() > 0) {
        const Eigen::VectorXd permuted = ldlt.permutationP() * index;
        for (std::size_t i = 0; i < n; ++i) permutation_[i] = static_cast<std::int32_t>(permuted[static_cast<Eigen::Index>(i)]);
    } else {
        for (std::size_t i = 0; i < n; ++i) permutation_[i] = static_cast<std::int32_t>(i);
    }

    // L: unit lower triangular; keep the strictly lower entries by column.
    const auto& l = ldlt.matrixL().nestedExpression();
    column_start_.assign(n + 1, 0);
    row_.clear();
    value_.clear();
    for (Eigen::Index j = 0; j < l.outerSize(); ++j) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(l, j); it; ++it) {
            if (it.row() > j) {
                row_.push_back(static_cast<std::int32_t>(it.row()));
                value_.push_back(it.value());
            }
        }
        column_start_[static_cast<std::size_t>(j) + 1] = static_cast<std::int32_t>(row_.size());
    }
    work_.assign(n, 0.0);
}

void SparseLdlt::solve(const double* b, double* x) const {
    const std::size_t n = diagonal_.size();
    double* __restrict y = work_.data();
    const std::int32_t* __restrict p = permutation_.data();
    const std::int32_t* __restrict cs = column_start_.data();
    const std::int32_t* __restrict row = row_.data();
    const double* __restrict val = value_.data();
    const double* __restrict d = diagonal_.data();
    for (std::size_t i = 0; i < n; ++i) y[i] = b[p[i]];
    // Forward: L y = P b, column by column (unit diagonal).
    for (std::size_t j = 0; j < n; ++j) {
        const double yj = y[j];
        for (std::int32_t k = cs[j]; k < cs[j + 1]; ++k) y[row[k]] -= val[k] * yj;
    }
    for (std::size_t i = 0; i < n; ++i) y[i] /= d[i];
    // Backward: L' z = y; row j of L' is column j of L.
    for (std::size_t j = n; j-- > 0;) {
        double s = y[j];
        for (std::int32_t k = cs[j]; k < cs[j + 1]; ++k) s -= val[k] * y[row[k]];
        y[j] = s;
    }
    for (std::size_t i = 0; i < n; ++i) x[p[i]] = y[i];
}

}  // namespace ameoto
