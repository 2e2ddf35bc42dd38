// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A symmetric positive definite sparse matrix factored once (build phase), solved many times without
// allocating (render phase). Shared by the implicit integrators (trapezoidal, backward Euler).
//
// Interface:
//   SparseLdlt s;
//   s.factor(A);                   // Eigen::SimplicialLDLT with AMD ordering: P A P' = L D L'; copies
//                                  // P, the unit lower L (compressed columns) and D. Allocates; throws
//                                  // std::invalid_argument unless A is positive definite.
//   s.solve(b, x);                 // x = A^-1 b (b and x of length n; may be the same array). No allocation.
//   s.size(), s.factor_nonzeros()
//
// Why not Eigen's solve(): SimplicialLDLT::_solve_impl ends with dest = Pinv * dest, an in-place
// permutation that allocates a mask vector on every call (Eigen 3.4, PermutationMatrix product). The
// triangular solves here are the textbook ones on the stored factor (Davis, Direct Methods for Sparse
// Linear Systems, 2006, ch. 3): forward L y = P b by columns, y /= D, backward L' z = y by dot products,
// x = P' z.

#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>

namespace ameoto {

class SparseLdlt {
public:
    void factor(const Eigen::SparseMatrix<double>& a);
    void solve(const double* b, double* x) const;

    std::size_t size() const { return diagonal_.size(); }
    std::size_t factor_nonzeros() const { return row_.size(); }

private:
    std::vector<std::int32_t> permutation_;   // (P b)_i = b[permutation_[i]]
    std::vector<std::int32_t> column_start_, row_;   // strictly lower part of L, by columns
    std::vector<double> value_, diagonal_;
    mutable std::vector<double> work_;
};

}  // namespace ameoto
