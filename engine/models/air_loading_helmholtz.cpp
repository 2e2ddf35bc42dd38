// SPDX-License-Identifier: GPL-3.0-or-later
// The air's complex mass on the umbrella at one frequency: see air_loading_helmholtz.hpp.
#include "engine/models/air_loading_helmholtz.hpp"

#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading_sectors.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto {

using cd = std::complex<double>;

std::complex<double> helmholtz_kernel_remainder(double k, double r) {
    const double x = k * r;
    const double four_pi = 4.0 * constants::pi;
    if (x < 0.05) {
        // (e^(-ix) (1 + ix) - 1) = sum_m (-i)^m (1 - m) / m! x^m (m >= 2); less the x^2 / 2 term, over r^3:
        // k^3 sum_(m >= 3) c_m x^(m - 3).
        cd sum = 0.0, power = 1.0;                  // x^(m - 3)
        cd minus_i_m = cd(0.0, 1.0);                // (-i)^3
        double factorial = 6.0;                     // 3!
        for (int m = 3; m <= 12; ++m) {
            sum += minus_i_m * (1.0 - m) / factorial * power;
            power *= x;
            minus_i_m *= cd(0.0, -1.0);
            factorial *= (m + 1);
        }
        return k * k * k * sum / four_pi;
    }
    const cd e = std::exp(cd(0.0, -x)) * cd(1.0, x) - 1.0 - 0.5 * x * x;
    return e / (four_pi * r * r * r);
}

double polygon_inverse_distance_integral(Point2 x, const std::vector<Point2>& corners) {
    // The fan of triangles (x, a, b) over the edges, each signed by its orientation: in polar coordinates
    // about x, integral dA / r = integral r_max(psi) dpsi, and along the edge's line r_max = h / cos(psi), so
    // a triangle gives h (asinh(t_b / h) - asinh(t_a / h)), t the coordinate along the edge from the foot
    // of the perpendicular, h the distance from x to the edge's line.
    double sum = 0.0;
    const std::size_t n = corners.size();
    for (std::size_t q = 0; q < n; ++q) {
        const Point2 a = corners[q], b = corners[(q + 1) % n];
        const double ex = b.x - a.x, ey = b.y - a.y, length = std::hypot(ex, ey);
        if (length == 0.0) continue;
        const double ux = ex / length, uy = ey / length;
        const double ax = a.x - x.x, ay = a.y - x.y;
        const double signed_h = ax * uy - ay * ux;   // (a - x) x u
        const double h = std::abs(signed_h);
        if (h < 1e-15 * length) continue;            // x on the edge's line: a triangle of no area
        const double ta = ax * ux + ay * uy, tb = ta + length;
        const double sign = signed_h < 0.0 ? 1.0 : -1.0;   // counter-clockwise (x, a, b): positive
        sum += sign * h * (std::asinh(tb / h) - std::asinh(ta / h));
    }
    return std::abs(sum);
}

namespace {

using namespace air_sectors;

// integral over the quad of D(|x - y|) dA (the header's D).
cd kernel_difference(Point2 x, const Quad& q, double k) {
    const double d = std::hypot(x.x - q.centroid.x, x.y - q.centroid.y);
    const double four_pi = 4.0 * constants::pi;
    if (d > 2.5 * q.size) {
        return integrate_quad(q, gauss2, [&](Point2 y) {
            const double r = std::hypot(x.x - y.x, x.y - y.y);
            return k * k / (2.0 * four_pi * r) + helmholtz_kernel_remainder(k, r);
        });
    }
    const double singular = k * k / (2.0 * four_pi) * polygon_inverse_distance_integral(x, q.polygon);
    return singular + integrate_quad(q, gauss3, [&](Point2 y) { return helmholtz_kernel_remainder(k, std::hypot(x.x - y.x, x.y - y.y)); });
}

struct Level {
    std::vector<Eigen::MatrixXcd> block;   // [d], nodes x nodes
};

// The rings' velocities with the Helmholtz kernel: Laplace's less each element's integral of D.
std::vector<Eigen::MatrixXcd> helmholtz_velocities(const Canopy& canopy, const std::vector<SectorCell>& cells,
                                                   const std::vector<SectorElement>& elements, const std::vector<Eigen::MatrixXd>& laplace,
                                                   double k) {
    const int panels = canopy.panel_count(), n = static_cast<int>(elements.size());
    std::vector<Eigen::MatrixXcd> g(static_cast<std::size_t>(panels));
    for (int d = 0; d < panels; ++d) {
        g[static_cast<std::size_t>(d)] = laplace[static_cast<std::size_t>(d)].cast<cd>();
        if (k == 0.0) continue;
        const double turn = canopy.panel_azimuth(d) - canopy.panel_azimuth(0);
        const double ct = std::cos(turn), st = std::sin(turn);
        std::vector<Quad> quads;
        quads.reserve(cells.size());
        for (const SectorCell& cell : cells) quads.push_back(turned_quad(cell, ct, st));
        for (int kk = 0; kk < n; ++kk)
            for (int i = 0; i < n; ++i) {
                cd w = 0.0;
                for (const std::size_t c : elements[static_cast<std::size_t>(kk)].cells)
                    w += kernel_difference(elements[static_cast<std::size_t>(i)].centroid, quads[c], k);
                g[static_cast<std::size_t>(d)](i, kk) -= w;
            }
    }
    return g;
}

// A level's air mass on the nodes as the N blocks of its block-circulant matrix (air_loading.cpp's
// sector_mass; every Fourier mode solved, as the kernel may be complex).
Level solve_level(const std::vector<Eigen::MatrixXcd>& g, const std::vector<SectorElement>& elements, int panels, int nodes,
                  double air_density) {
    const int n = static_cast<int>(elements.size());
    Eigen::MatrixXcd owner = Eigen::MatrixXcd::Zero(n, nodes);
    Eigen::VectorXd area(n);
    for (int c = 0; c < n; ++c) {
        owner(c, elements[static_cast<std::size_t>(c)].node) = 1.0;
        area[c] = elements[static_cast<std::size_t>(c)].area;
    }
    const Eigen::MatrixXcd weighted_owner = owner.transpose() * area.cast<cd>().asDiagonal();
    Level out;
    out.block.assign(static_cast<std::size_t>(panels), Eigen::MatrixXcd::Zero(nodes, nodes));
    for (int m = 0; m < panels; ++m) {
        const double theta = 2.0 * constants::pi * m / panels;
        Eigen::MatrixXcd gm = Eigen::MatrixXcd::Zero(n, n);
        for (int d = 0; d < panels; ++d) gm += std::polar(1.0, theta * d) * g[static_cast<std::size_t>(d)];
        const Eigen::MatrixXcd h = air_density * weighted_owner * gm.partialPivLu().solve(owner);
        for (int d = 0; d < panels; ++d) out.block[static_cast<std::size_t>(d)] += (1.0 / panels) * std::polar(1.0, -theta * d) * h;
    }
    return out;
}

Eigen::MatrixXcd assemble(const std::vector<Eigen::MatrixXcd>& blocks, int panels, int nodes) {
    Eigen::MatrixXcd m(panels * nodes, panels * nodes);
    for (int p = 0; p < panels; ++p)
        for (int q = 0; q < panels; ++q)
            m.block(p * nodes, q * nodes, nodes, nodes) = blocks[static_cast<std::size_t>((q - p + panels) % panels)];
    return m;
}

}  // namespace

Eigen::MatrixXcd CanopyAirImpedance::matrix() const {
    std::vector<Eigen::MatrixXcd> blocks(static_cast<std::size_t>(panels), Eigen::MatrixXcd::Zero(nodes, nodes));
    for (int d = 0; d < panels; ++d)
        for (int m = 0; m < panels; ++m)
            blocks[static_cast<std::size_t>(d)] +=
                (1.0 / panels) * std::polar(1.0, -2.0 * constants::pi * m * d / panels) * fourier[static_cast<std::size_t>(m)];
    return assemble(blocks, panels, nodes);
}

CanopyAirImpedanceBuilder::CanopyAirImpedanceBuilder(const Canopy& canopy, double air_density, double speed_of_sound,
                                                     const CanopyAirMassOptions& options)
    : air_density_(air_density), speed_of_sound_(speed_of_sound), panels_(canopy.panel_count()), nodes_(canopy.nodes_per_panel()),
      canopy_(&canopy) {
    if (options.rows < 2 || options.rows % 2) throw std::invalid_argument("canopy air impedance: an even number of rows, at least 2");
    if (!(air_density > 0.0)) throw std::invalid_argument("canopy air impedance: the air's density must be positive");
    if (!(speed_of_sound > 0.0)) throw std::invalid_argument("canopy air impedance: the speed of sound must be positive");
    cells_ = sector_cells(canopy, options.rows);
    elements_ = single_elements(cells_);
    laplace_ = ring_velocities(canopy, cells_, elements_);
    static_correction_.assign(static_cast<std::size_t>(panels_), Eigen::MatrixXcd::Zero(nodes_, nodes_));
    if (options.extrapolate) {
        // Richardson at omega = 0 only: M(0) = (r2 M_fine - r1 M_coarse) / (r2 - r1), kept as the correction
        // r1 (M_fine - M_coarse) / (r2 - r1) added to the finer level at every frequency.
        const std::vector<SectorElement> coarse_elements = grouped_elements(cells_, nodes_);
        std::vector<Eigen::MatrixXcd> coarse_g;
        for (const Eigen::MatrixXd& g : ring_velocities(canopy, cells_, coarse_elements)) coarse_g.push_back(g.cast<cd>());
        std::vector<Eigen::MatrixXcd> fine_g;
        for (const Eigen::MatrixXd& g : laplace_) fine_g.push_back(g.cast<cd>());
        const Level fine = solve_level(fine_g, elements_, panels_, nodes_, air_density);
        const Level coarse = solve_level(coarse_g, coarse_elements, panels_, nodes_, air_density);
        const double r2 = options.rows, r1 = 0.5 * options.rows;
        for (int d = 0; d < panels_; ++d)
            static_correction_[static_cast<std::size_t>(d)] =
                r1 / (r2 - r1) * (fine.block[static_cast<std::size_t>(d)] - coarse.block[static_cast<std::size_t>(d)]);
    }
}

CanopyAirImpedance CanopyAirImpedanceBuilder::at(double omega) const {
    if (!(omega >= 0.0)) throw std::invalid_argument("canopy air impedance: the frequency must not be negative");
    const double k = omega / speed_of_sound_;
    Level level = solve_level(helmholtz_velocities(*canopy_, cells_, elements_, laplace_, k), elements_, panels_, nodes_, air_density_);
    // The static extrapolation, then symmetrised as canopy_added_mass's: the transpose's block d is block -d
    // transposed.
    for (int d = 0; d < panels_; ++d) level.block[static_cast<std::size_t>(d)] += static_correction_[static_cast<std::size_t>(d)];
    std::vector<Eigen::MatrixXcd> sym(level.block.size());
    for (int d = 0; d < panels_; ++d)
        sym[static_cast<std::size_t>(d)] =
            0.5 * (level.block[static_cast<std::size_t>(d)] + level.block[static_cast<std::size_t>((panels_ - d) % panels_)].transpose());
    CanopyAirImpedance out;
    out.omega = omega;
    out.panels = panels_;
    out.nodes = nodes_;
    out.fourier.assign(static_cast<std::size_t>(panels_), Eigen::MatrixXcd::Zero(nodes_, nodes_));
    for (int m = 0; m < panels_; ++m)
        for (int d = 0; d < panels_; ++d)
            out.fourier[static_cast<std::size_t>(m)] += std::polar(1.0, 2.0 * constants::pi * m * d / panels_) * sym[static_cast<std::size_t>(d)];
    return out;
}

CanopyAirImpedance canopy_air_mass_at(const Canopy& canopy, double air_density, double speed_of_sound, double omega,
                                      const CanopyAirMassOptions& options) {
    if (!(omega >= 0.0)) throw std::invalid_argument("canopy air impedance: the frequency must not be negative");
    return CanopyAirImpedanceBuilder(canopy, air_density, speed_of_sound, options).at(omega);
}

}  // namespace ameoto
