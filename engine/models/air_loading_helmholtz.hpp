// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The air's mass on the umbrella at one frequency, with the air compressible: the complex added mass
// M_a(omega) of the canopy's nodes, both faces loaded, no baffle. Its real part is the air's mass (the
// evanescent layer grows as a wave nears the speed of sound); its imaginary part is the radiation
// resistance, -omega Im M_a. At omega -> 0 it is air_loading.hpp's incompressible M_a.
//
// Interface (build phase only: allocates; the default canopy's takes about 0.8 s of CPU, or with a
// builder 0.4 s once and 0.45 s a frequency: 2026-12-06, a loaded 2-core VM):
//   CanopyAirImpedance z = canopy_air_mass_at(canopy, rho0, c, omega);   // omega in rad/s
//   CanopyAirImpedanceBuilder b(canopy, rho0, c);  b.at(omega)            // the same at many frequencies
//   z.fourier[m]    // nodes x nodes, kg: M_a on the panels' Fourier mode m (x_p = e^(i 2 pi m p / N) y)
//   z.matrix()      // the whole canopy's (panel-major), complex symmetric
//   The force the air takes from the canopy is F = M_a(omega) u'' for u ~ e^(i omega t).
//
// Method: air_loading.hpp's doublet sheet with the Helmholtz kernel in place of Laplace's. A screen's
// normal velocity from a doublet sheet mu is w(x) = -(1 / 4 pi) f.p. integral mu(y) K(|x - y|) dA with
// K = d^2/dn dn' (e^(-ikR) / R) = e^(-ikr) (1 + ikr) / r^3 on the plane (r in the plane; Laplace's 1 / r^3
// at k = 0; Colton & Kress, Integral Equation Methods in Scattering Theory, 1983, section 3.1, the
// hypersingular operator). The difference D(r) = (e^(-ikr) (1 + ikr) - 1) / (4 pi r^3) is weakly singular,
// D = k^2 / (8 pi r) - i k^3 / (12 pi) + O(r), so the vortex rings keep the hypersingular part and each
// element's ring velocity G_ij loses integral_j D(|x_i - y|) dA: the 1 / r part exactly (a polygon's
// integral of 1 / r from a point, by its edges), the rest by Gauss-Legendre on the sub-cell (3 x 3 near,
// 2 x 2 beyond 2.5 sub-cell sizes). On a plane wave e^(i kappa x) this gives G = sqrt(kappa^2 - k^2) / 2
// (Laplace's kappa / 2): the air's mass per area rho0 / sqrt(kappa^2 - k^2) per face (acoustics.md
// section 1), and for kappa < k a radiation resistance. Sampling, Fourier blocks over the panels and
// Richardson's step are canopy_added_mass's (air_loading.hpp), but the step is taken at omega = 0 only
// and added to the finer level at every frequency: the coarser level's 4 cm elements have kh near 3 at
// 4 kHz, out of the O(h) regime the step assumes (extrapolating there put the 4 kHz forces 7 dB off the
// reference; the finer level alone, within 3 dB). The incompressible step is the near field's, which the
// frequency hardly changes. (canopy_added_mass's fall-back, for the rows whose step is indefinite, is not
// repeated: the default 24 / 12 is not one of them.)
// Time dependence e^(i omega t), outgoing waves e^(-ikr): a passive screen has Im M_a <= 0.

#include <complex>
#include <vector>

#include <Eigen/Dense>

#include "engine/models/air_loading.hpp"
#include "engine/models/air_loading_sectors.hpp"

namespace ameoto {

struct CanopyAirImpedance {
    double omega = 0.0;                      // rad/s
    int panels = 0, nodes = 0;               // nodes per panel
    std::vector<Eigen::MatrixXcd> fourier;   // [m = 0..panels-1], nodes x nodes, kg
    Eigen::MatrixXcd matrix() const;         // panels * nodes square: block (p, q) is
                                             // (1 / N) sum_m e^(-i theta_m (q - p)) fourier[m], theta_m = 2 pi m / N
};

// Throws std::invalid_argument for omega < 0, a density or speed <= 0, or options canopy_added_mass refuses.
CanopyAirImpedance canopy_air_mass_at(const Canopy& canopy, double air_density, double speed_of_sound, double omega,
                                      const CanopyAirMassOptions& options = {});

// The same at many frequencies: the sampling, the rings' Laplace velocities and the static extrapolation
// once (0.4 s), then about 0.45 s a frequency. Keeps a pointer to the canopy, which must outlive it.
class CanopyAirImpedanceBuilder {
public:
    CanopyAirImpedanceBuilder(const Canopy& canopy, double air_density, double speed_of_sound, const CanopyAirMassOptions& options = {});
    CanopyAirImpedance at(double omega) const;

private:
    double air_density_, speed_of_sound_;
    int panels_, nodes_;
    const Canopy* canopy_;
    std::vector<air_sectors::SectorCell> cells_;
    std::vector<air_sectors::SectorElement> elements_;
    std::vector<Eigen::MatrixXd> laplace_;                  // [d]: the finer level's ring velocities
    std::vector<Eigen::MatrixXcd> static_correction_;       // [d]: Richardson's step at omega = 0, kg
};

// The kernel's difference from Laplace's, D(r) = (e^(-ikr) (1 + ikr) - 1) / (4 pi r^3), less its 1 / r part
// k^2 / (8 pi r): smooth, -i k^3 / (12 pi) at r = 0 (series below kr = 0.05). Exposed for its test.
std::complex<double> helmholtz_kernel_remainder(double k, double r);
// integral over the polygon (corners in order, either sense) of 1 / |x - y| dA_y, m. Exposed for its test.
double polygon_inverse_distance_integral(Point2 x, const std::vector<Point2>& corners);

}  // namespace ameoto
