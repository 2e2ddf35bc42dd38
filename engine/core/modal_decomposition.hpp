// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Normal modes of a linear transverse network: K phi = omega^2 M phi.
//
// Interface:
//   ModalDecomposition d = decompose_modes(arrays);     // every mode, dense (up to a few thousand masses)
//   d.omega[k]               // rad/s, ascending, undamped
//   d.shapes.col(k)          // phi_k, mass-normalised: Phi' M Phi = I
//   d.damping_rate[k]        // s_k = (Phi' C Phi)_kk / 2, 1/s: the mode decays like exp(-s_k t)
//   d.net_force_weight[k]    // w_k = sum_i m_i phi_ik: the mode's share of the momentum, sum m v = w'q'
//   d.non_proportionality    // max |(Phi' C Phi)_jk| / sqrt(.._jj .._kk), j != k: 0 for C = a M + b K
//   RayleighDamping r = rayleigh_damping(arrays);     // C = alpha M + beta K read off the elements
//   LowestModes l = lowest_modes(arrays, count);      // the `count` lowest, sparse (large lattices)
//
// Method: M is diagonal, so A = M^-1/2 K M^-1/2 is symmetric with the same eigenvalues omega^2; Eigen's
// SelfAdjointEigenSolver gives A = U diag(omega^2) U', and Phi = M^-1/2 U is mass-normalised. Damping:
// proportional (Rayleigh) damping C = alpha M + beta K is diagonal in the modes, s_k = (alpha + beta
// omega_k^2) / 2; any other C is diagonalised approximately by keeping the diagonal of Phi' C Phi
// (classical modal damping), and non_proportionality says how much coupling that drops.
// Recovering alpha and beta (rayleigh_damping): every link's damper over its spring gives beta (they
// must agree); then each mass's ground damper minus beta times its anchor stiffness, over its mass,
// gives alpha (they must agree). `exact` says whether they did, to a relative 1e-9.
// lowest_modes: subspace iteration with Rayleigh-Ritz (Bathe, Finite Element Procedures, 1996,
// section 11.6) on (K + sigma M)^-1 M, sigma > 0 a small shift so free bodies (K singular) work; the
// factor is the sparse LDLT of integrators/sparse_ldlt.hpp, so a 2000-mass lattice takes milliseconds.

#include <Eigen/Dense>

#include "engine/core/integrators/network_arrays.hpp"

namespace ameoto {

struct ModalDecomposition {
    Eigen::VectorXd omega;
    Eigen::MatrixXd shapes;
    Eigen::VectorXd damping_rate;
    Eigen::VectorXd net_force_weight;
    double non_proportionality = 0.0;
};

ModalDecomposition decompose_modes(const NetworkArrays& arrays);

struct RayleighDamping {
    bool exact = false;
    double alpha = 0.0;   // 1/s
    double beta = 0.0;    // s
};

RayleighDamping rayleigh_damping(const NetworkArrays& arrays);

struct LowestModes {
    Eigen::VectorXd omega;    // rad/s, ascending
    Eigen::MatrixXd shapes;   // mass-normalised
    int iterations = 0;
};

// Throws std::invalid_argument if count < 1 or count > mass count, or if it does not converge to a
// relative 1e-12 in the eigenvalues within max_iterations.
LowestModes lowest_modes(const NetworkArrays& arrays, int count, int max_iterations = 500);

}  // namespace ameoto
