// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/modal_decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/integrators/sparse_ldlt.hpp"

namespace ameoto {

ModalDecomposition decompose_modes(const NetworkArrays& arrays) {
    const auto n = static_cast<Eigen::Index>(arrays.mass_count());
    ModalDecomposition d;
    if (n == 0) return d;
    Eigen::VectorXd inv_sqrt_m(n), m(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        m[i] = arrays.mass(static_cast<std::size_t>(i));
        inv_sqrt_m[i] = 1.0 / std::sqrt(m[i]);
    }
    const Eigen::MatrixXd k = Eigen::MatrixXd(arrays.stiffness_matrix());
    const Eigen::MatrixXd a = inv_sqrt_m.asDiagonal() * k * inv_sqrt_m.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(a);
    if (solver.info() != Eigen::Success) throw std::runtime_error("decompose_modes: eigen-solve failed");
    d.omega = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    d.shapes = inv_sqrt_m.asDiagonal() * solver.eigenvectors();
    const Eigen::MatrixXd c = Eigen::MatrixXd(arrays.damping_matrix());
    const Eigen::MatrixXd modal_c = d.shapes.transpose() * c * d.shapes;
    d.damping_rate = 0.5 * modal_c.diagonal();
    d.net_force_weight = d.shapes.transpose() * m;
    for (Eigen::Index j = 0; j < n; ++j) {
        for (Eigen::Index l = 0; l < n; ++l) {
            if (j == l) continue;
            const double scale = std::sqrt(std::abs(modal_c(j, j) * modal_c(l, l)));
            if (scale > 0.0) d.non_proportionality = std::max(d.non_proportionality, std::abs(modal_c(j, l)) / scale);
            else if (modal_c(j, l) != 0.0) d.non_proportionality = std::max(d.non_proportionality, 1.0);
        }
    }
    return d;
}

RayleighDamping rayleigh_damping(const NetworkArrays& arrays) {
    constexpr double tolerance = 1e-9;
    RayleighDamping r;
    auto agree = [&](double a, double b) { return std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b)); };
    bool exact = true;
    bool have_beta = false;
    for (std::size_t l = 0; l < arrays.link_count(); ++l) {
        if (arrays.link_stiffness[l] == 0.0) {
            exact = exact && arrays.link_damping[l] == 0.0;
            continue;
        }
        const double b = arrays.link_damping[l] / arrays.link_stiffness[l];
        if (!have_beta) {
            r.beta = b;
            have_beta = true;
        } else {
            exact = exact && agree(b, r.beta);
        }
    }
    // alpha_i = (z_i - beta k_i) / m_i; compared on the scale of its terms (the subtraction cancels).
    double scale0 = 0.0;
    for (std::size_t i = 0; i < arrays.mass_count(); ++i) {
        const double a = (arrays.ground_damping[i] - r.beta * arrays.anchor_stiffness[i]) / arrays.mass(i);
        const double scale = (std::abs(arrays.ground_damping[i]) + std::abs(r.beta * arrays.anchor_stiffness[i])) / arrays.mass(i);
        if (i == 0) {
            r.alpha = a;
            scale0 = scale;
        } else {
            exact = exact && std::abs(a - r.alpha) <= tolerance * std::max(scale, scale0);
        }
    }
    r.exact = exact;
    return r;
}

LowestModes lowest_modes(const NetworkArrays& arrays, int count, int max_iterations) {
    const auto n = static_cast<Eigen::Index>(arrays.mass_count());
    if (count < 1 || count > n) throw std::invalid_argument("lowest_modes: count must be 1 .. mass count");
    const Eigen::Index p = count;
    const Eigen::Index q = std::min<Eigen::Index>(n, std::max<Eigen::Index>(2 * p, p + 8));
    Eigen::VectorXd m(n);
    for (Eigen::Index i = 0; i < n; ++i) m[i] = arrays.mass(static_cast<std::size_t>(i));
    const Eigen::SparseMatrix<double> k = arrays.stiffness_matrix();
    // Shift: a small fraction of the mean diagonal of M^-1 K keeps K + sigma M definite for free bodies
    // without hurting the convergence ratio (lambda_p + sigma) / (lambda_q+1 + sigma).
    double mean = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) mean += k.coeff(i, i) / m[i];
    mean /= static_cast<double>(n);
    const double sigma = 1e-6 * std::max(mean, 1e-300);
    Eigen::SparseMatrix<double> shifted = k;
    for (Eigen::Index i = 0; i < n; ++i) shifted.coeffRef(i, i) += sigma * m[i];
    SparseLdlt solver;
    solver.factor(shifted);

    // Start: deterministic, rich in every mode (a low-discrepancy fill, not a smooth shape).
    Eigen::MatrixXd x(n, q);
    for (Eigen::Index j = 0; j < q; ++j)
        for (Eigen::Index i = 0; i < n; ++i) x(i, j) = std::sin(1.0 + 0.7548776662 * static_cast<double>(i + 1) * static_cast<double>(j + 1) + 0.5698402910 * static_cast<double>(i));
    Eigen::MatrixXd y(n, q);
    Eigen::VectorXd previous = Eigen::VectorXd::Constant(p, -1.0);
    LowestModes out;
    for (int it = 1; it <= max_iterations; ++it) {
        for (Eigen::Index j = 0; j < q; ++j) {
            const Eigen::VectorXd rhs = m.asDiagonal() * x.col(j);
            solver.solve(rhs.data(), y.col(j).data());
        }
        const Eigen::MatrixXd kr = y.transpose() * (shifted * y);
        const Eigen::MatrixXd mr = y.transpose() * m.asDiagonal() * y;
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(0.5 * (kr + kr.transpose()), 0.5 * (mr + mr.transpose()));
        if (ritz.info() != Eigen::Success) throw std::runtime_error("lowest_modes: Ritz eigen-solve failed");
        x = y * ritz.eigenvectors();   // M-orthonormal
        const Eigen::VectorXd lambda = ritz.eigenvalues().head(p);
        const double change = ((lambda - previous).array().abs() / lambda.array().abs().max(1e-300)).maxCoeff();
        previous = lambda;
        if (change < 1e-13) {
            out.omega = (lambda.array() - sigma).max(0.0).sqrt().matrix();
            out.shapes = x.leftCols(p);
            out.iterations = it;
            return out;
        }
    }
    throw std::invalid_argument("lowest_modes: subspace iteration did not converge");
}

}  // namespace ameoto
