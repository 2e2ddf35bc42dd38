// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The linear mass-spring-damper network every integrator reads: masses, links to other masses,
// anchors to fixed points, as structure-of-arrays. Transverse (1-D per node) displacement.
//
// Interface:
//   NetworkArrays a;                              // filled by TransverseNetwork::add_* (build phase)
//   a.mass_count(), a.link_count(), a.mass(i)
//   a.forces(x, v, ext, f)                        // f = ext - K x - C v (v may be null: no damping)
//   a.energy(x, v)                                // 1/2 v'Mv + 1/2 x'Kx, J
//   a.stiffness_matrix(), a.damping_matrix()      // K, C as Eigen sparse (build phase, allocates)
//
// Equations: the network's equation of motion is M x'' + C x' + K x = f_ext with M diagonal and
//   K = sum over links l of k_l (e_a - e_b)(e_a - e_b)' + diag(anchor stiffness),
//   C = sum over links l of z_l (e_a - e_b)(e_a - e_b)' + diag(ground and anchor damping),
// i.e. the CORDIS-ANIMA link F1 = -F2 = -k (x1 - x2) - z (v1 - v2) (seed section 4.1) with zero rest
// length. The links' columns of K and C sum to zero, so 1'K x = sum_i anchor_i x_i and internal forces
// cancel in any sum over masses (Newton's third law): the momentum of a free network is conserved.

#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>

namespace ameoto {

struct NetworkArrays {
    // masses
    std::vector<double> mass_kg, inverse_mass, ground_damping, anchor_stiffness;
    // links
    std::vector<std::int32_t> link_a, link_b;
    std::vector<double> link_stiffness, link_damping;

    std::size_t mass_count() const { return inverse_mass.size(); }
    std::size_t link_count() const { return link_a.size(); }
    double mass(std::size_t i) const { return mass_kg[i]; }

    // f = ext - K x - C v, written into f (length mass_count). v == nullptr: the damping is left out.
    // ext == nullptr: no external force. No allocation.
    void forces(const double* x, const double* v, const double* ext, double* f) const;

    // 1/2 v' M v + 1/2 x' K x (J). v == nullptr: potential energy only.
    double energy(const double* x, const double* v) const;

    Eigen::SparseMatrix<double> stiffness_matrix() const;
    Eigen::SparseMatrix<double> damping_matrix() const;
};

}  // namespace ameoto
