// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the air's compressibility does to the canopy's in-phase air mass (every panel moving alike) at
// low frequency, cheaply enough for a scene's build: the Fourier block m = 0 of M_a(omega) - M_a(0)
// (air_loading_helmholtz.hpp), from a series in the wavenumber whose terms are computed once.
//
// Interface (build phase only: allocates; the default canopy's to 170 Hz takes about 0.1 s of CPU):
//   InPhaseAirMass a(canopy, rho0, c, max_omega);   // omega in rad/s: the highest change_at will be asked
//   Eigen::MatrixXcd d = a.change_at(omega);         // panel 0's nodes x nodes, kg, complex symmetric:
//                                                    // (omega real, or complex: a.change_at(cd(w, s)))
//                                                    // a panel's share of the in-phase block's change
//   For a whole-canopy vector phi = (psi, psi, ..., psi) (N panels alike), phi' (M_a(omega) - M_a(0)) phi
//   = N psi' d psi. Its real part is the air's extra mass (the evanescent layer thickens as a wave nears
//   the speed of sound), its imaginary part -1 / omega times the radiation resistance (Im <= 0: passive).
//
// Why the in-phase block: those modes move the most air (a net volume swept, the air's mass reaching a
// canopy's size out, where kr is not small); the incompressible mass is 4.4 % too light for the lowest
// (docs/canopy-air.md, "The compressible poles of the in-phase modes"), where the other blocks' modes move
// under 1.6 %.
//
// Method. CanopyAirImpedanceBuilder's rings with the Helmholtz kernel: G(k) = G(0) - integral D, with
// D(r) = (e^(-ikr) (1 + ikr) - 1) / (4 pi r^3) = sum_(m >= 2) a_m k^m r^(m - 3) / (4 pi),
// a_m = (-i)^m (1 - m) / m! (the exponential's series). Each term's integral P_m(i, j) = sum_d integral over
// panel d's cell j of r^(m - 3) dA from panel 0's collocation point i is independent of k, so one pass of
// the quadrature (real, no exponential) gives the in-phase block of G at every k below max_omega / c:
// G_0(k) = sum_d g_d(0) - sum_m a_m k^m P_m / (4 pi). The quadrature is the builder's (the 1 / r term
// exactly by the cell's edges near the point, Gauss-Legendre 3 x 3 near and 2 x 2 beyond 2.5 cell sizes),
// so change_at equals the builder's fourier[0] difference to the series' truncation, which is chosen
// below 1e-12 of the largest term at k r_max (r_max the canopy's diameter). The static Richardson step
// (the builder's) is the same at every frequency and cancels in the difference.

#include <complex>
#include <vector>

#include <Eigen/Dense>

#include "engine/models/air_loading.hpp"

namespace ameoto {

class Canopy;

class InPhaseAirMass {
public:
    // Throws std::invalid_argument for a density or speed <= 0, max_omega < 0, or rows canopy_added_mass
    // refuses.
    InPhaseAirMass(const Canopy& canopy, double air_density, double speed_of_sound, double max_omega,
                   const CanopyAirMassOptions& options = {});
    // Throws std::invalid_argument for omega outside 0..max_omega.
    Eigen::MatrixXcd change_at(double omega) const;
    // The same continued to a complex frequency (the series is a polynomial in k): where a pole is, the
    // canopy's free motion e^(i omega t) decays at Im omega. Throws for |omega| > max_omega.
    Eigen::MatrixXcd change_at(std::complex<double> omega) const;
    double max_omega() const { return max_omega_; }
    int terms() const { return static_cast<int>(series_.rows()); }   // m = 2 .. terms() + 1

private:
    Eigen::MatrixXcd block_mass(std::complex<double> k) const;   // rho0 P0' diag(A) G_0(k)^-1 P0, nodes x nodes

    double air_density_, speed_of_sound_, max_omega_;
    int nodes_;
    Eigen::MatrixXd laplace_;               // sum_d g_d(0), elements x elements
    Eigen::MatrixXd series_;                // (m - 2, j * n + i): P_m(i, j) / (4 pi)
    Eigen::MatrixXd owner_;                 // elements x nodes, 0 / 1
    Eigen::MatrixXd weighted_owner_;        // nodes x elements: owner' diag(area)
    Eigen::MatrixXcd static_mass_;          // block_mass(0)
};

}  // namespace ameoto
