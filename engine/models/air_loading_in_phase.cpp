// SPDX-License-Identifier: GPL-3.0-or-later
// The in-phase block of the compressible air mass by the kernel's series: see air_loading_in_phase.hpp.
#include "engine/models/air_loading_in_phase.hpp"

#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading_helmholtz.hpp"
#include "engine/models/air_loading_sectors.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto {

namespace {

using cd = std::complex<double>;
using namespace air_sectors;

// The series' length for k r up to x: terms a_m x^m, |a_m| = (m - 1) / m!, kept until they fall under
// 1e-12 of the largest (past the largest, m > x, they fall faster than geometrically).
int series_terms(double x) {
    double term = 0.5 * x * x, largest = term;   // m = 2
    int m = 2;
    while (m < 200) {
        const double next = term * x * m / ((m + 1.0) * (m - 1.0));   // (m / (m - 1)) x / (m + 1) times the last
        ++m;
        term = next;
        largest = std::max(largest, term);
        if (m > x && term < 1e-12 * largest) break;
    }
    return m - 1;   // m = 2 .. m_last: m_last - 1 terms
}

}  // namespace

InPhaseAirMass::InPhaseAirMass(const Canopy& canopy, double air_density, double speed_of_sound, double max_omega,
                               const CanopyAirMassOptions& options)
    : air_density_(air_density), speed_of_sound_(speed_of_sound), max_omega_(max_omega), nodes_(canopy.nodes_per_panel()) {
    if (options.rows < 2 || options.rows % 2) throw std::invalid_argument("in-phase air mass: an even number of rows, at least 2");
    if (!(air_density > 0.0)) throw std::invalid_argument("in-phase air mass: the air's density must be positive");
    if (!(speed_of_sound > 0.0)) throw std::invalid_argument("in-phase air mass: the speed of sound must be positive");
    if (!(max_omega >= 0.0) || !std::isfinite(max_omega)) throw std::invalid_argument("in-phase air mass: the highest frequency must not be negative");
    const std::vector<SectorCell> cells = sector_cells(canopy, options.rows);
    // The builder's finer level, one cell an element: the coarser (78 a panel) put the second in-phase
    // mode's radiation at 3.8 /s against the finer's 4.7.
    const std::vector<SectorElement> elements = single_elements(cells);
    const int n = static_cast<int>(elements.size()), panels = canopy.panel_count();

    laplace_ = Eigen::MatrixXd::Zero(n, n);
    for (const Eigen::MatrixXd& g : ring_velocities(canopy, cells, elements)) laplace_ += g;

    const double k_max = max_omega / speed_of_sound;
    const int last = k_max > 0.0 ? series_terms(k_max * 2.0 * canopy.geometry().radius_m) : 1;   // the series' last m
    const int terms = last - 1;
    // Laid out term-fastest per element pair, series_(t, j * n + i): one pass writes each pair's terms
    // together, and block_mass sums them as one matrix-vector product per part.
    series_.resize(terms, static_cast<Eigen::Index>(n) * n);
    // Each cell turned to each panel, with its rules' points: far off 2 x 2, near 3 x 3 (the builder's).
    struct Turned {
        Quad quad;
        double near_x[9], near_y[9], near_w[9], far_x[4], far_y[4], far_w[4];
    };
    const int cell_count = static_cast<int>(cells.size());
    std::vector<Turned> turned(static_cast<std::size_t>(panels) * cells.size());
    for (int d = 0; d < panels; ++d) {
        const double turn = canopy.panel_azimuth(d) - canopy.panel_azimuth(0);
        const double ct = std::cos(turn), st = std::sin(turn);
        for (int j = 0; j < cell_count; ++j) {
            Turned& c = turned[static_cast<std::size_t>(j) * static_cast<std::size_t>(panels) + static_cast<std::size_t>(d)];
            c.quad = turned_quad(cells[static_cast<std::size_t>(j)], ct, st);
            int a = 0;
            for_each_quad_point(c.quad, gauss3, [&](Point2 y, double w) { c.near_x[a] = y.x, c.near_y[a] = y.y, c.near_w[a++] = w; });
            a = 0;
            for_each_quad_point(c.quad, gauss2, [&](Point2 y, double w) { c.far_x[a] = y.x, c.far_y[a] = y.y, c.far_w[a++] = w; });
        }
    }
    const double four_pi = 4.0 * constants::pi;
    std::vector<double> sum(static_cast<std::size_t>(terms));
    for (int j = 0; j < n && terms > 0; ++j) {
        for (int i = 0; i < n; ++i) {
            const Point2 x = elements[static_cast<std::size_t>(i)].centroid;
            std::fill(sum.begin(), sum.end(), 0.0);
            for (const std::size_t cell : elements[static_cast<std::size_t>(j)].cells)
            for (int d = 0; d < panels; ++d) {   // the in-phase block: every panel's cell j, summed
                const Turned& c = turned[cell * static_cast<std::size_t>(panels) + static_cast<std::size_t>(d)];
                const bool far = std::hypot(x.x - c.quad.centroid.x, x.y - c.quad.centroid.y) > 2.5 * c.quad.size;
                if (far) {
                    double r[4], p[4];
                    for (int a = 0; a < 4; ++a) {
                        r[a] = std::sqrt((x.x - c.far_x[a]) * (x.x - c.far_x[a]) + (x.y - c.far_y[a]) * (x.y - c.far_y[a]));
                        p[a] = c.far_w[a];   // weight r^0: m = 3
                    }
                    sum[0] += c.far_w[0] / r[0] + c.far_w[1] / r[1] + c.far_w[2] / r[2] + c.far_w[3] / r[3];   // m = 2
                    for (int t = 1; t < terms; ++t) {   // m = t + 2: weight r^(m - 3)
                        sum[static_cast<std::size_t>(t)] += (p[0] + p[1]) + (p[2] + p[3]);
                        for (int a = 0; a < 4; ++a) p[a] *= r[a];
                    }
                } else {
                    double r[9], p[9];
                    for (int a = 0; a < 9; ++a) {
                        r[a] = std::sqrt((x.x - c.near_x[a]) * (x.x - c.near_x[a]) + (x.y - c.near_y[a]) * (x.y - c.near_y[a]));
                        p[a] = c.near_w[a];
                    }
                    sum[0] += polygon_inverse_distance_integral(x, c.quad.polygon);   // 1 / r exactly, by the edges
                    for (int t = 1; t < terms; ++t) {
                        double s = 0.0;
                        for (int a = 0; a < 9; ++a) {
                            s += p[a];
                            p[a] *= r[a];
                        }
                        sum[static_cast<std::size_t>(t)] += s;
                    }
                }
            }
            double* out = series_.data() + (static_cast<std::ptrdiff_t>(j) * n + i) * terms;
            for (int t = 0; t < terms; ++t) out[t] = sum[static_cast<std::size_t>(t)] / four_pi;
        }
    }

    owner_ = Eigen::MatrixXd::Zero(n, nodes_);
    Eigen::VectorXd area(n);
    for (int c = 0; c < n; ++c) {
        owner_(c, elements[static_cast<std::size_t>(c)].node) = 1.0;
        area[c] = elements[static_cast<std::size_t>(c)].area;
    }
    weighted_owner_ = owner_.transpose() * area.asDiagonal();
    static_mass_ = block_mass(0.0);
}

Eigen::MatrixXcd InPhaseAirMass::block_mass(std::complex<double> k) const {
    // G_0(k) = laplace - sum_m a_m k^m P_m / (4 pi), the coefficients' real and imaginary parts each one
    // matrix-vector product with the terms (for a real k the even terms are real, the odd imaginary).
    const auto terms = series_.rows();
    Eigen::RowVectorXd re_c(terms), im_c(terms);
    cd a_k = 0.5 * k * k;   // a_2 k^2 = (-i)^2 (1 - 2) / 2! k^2
    for (Eigen::Index t = 0; t < terms; ++t) {
        const int m = static_cast<int>(t) + 2;
        re_c[t] = a_k.real();
        im_c[t] = a_k.imag();
        // a_(m+1) k^(m+1) = a_m k^m (-i k) (1 - (m + 1)) / ((1 - m) (m + 1))
        a_k *= cd(0.0, -1.0) * k * (-static_cast<double>(m)) / ((1.0 - m) * (m + 1.0));
    }
    const auto n = laplace_.rows();
    Eigen::MatrixXcd g = laplace_.cast<cd>();
    if (terms > 0 && k != 0.0) {
        const Eigen::RowVectorXd re = re_c * series_, im = im_c * series_;   // 1 x n^2, element (j * n + i)
        for (Eigen::Index j = 0; j < n; ++j)
            for (Eigen::Index i = 0; i < n; ++i) g(i, j) -= cd(re[j * n + i], im[j * n + i]);
    }
    return air_density_ * weighted_owner_.cast<cd>() * g.partialPivLu().solve(owner_.cast<cd>());
}

Eigen::MatrixXcd InPhaseAirMass::change_at(double omega) const {
    if (!(omega >= 0.0 && omega <= max_omega_)) throw std::invalid_argument("in-phase air mass: the frequency is outside 0 .. the highest built for");
    return change_at(std::complex<double>(omega, 0.0));
}

Eigen::MatrixXcd InPhaseAirMass::change_at(std::complex<double> omega) const {
    if (!(std::abs(omega) <= max_omega_)) throw std::invalid_argument("in-phase air mass: |omega| is beyond the highest built for");
    const Eigen::MatrixXcd d = block_mass(omega / speed_of_sound_) - static_mass_;
    return 0.5 * (d + d.transpose());
}

}  // namespace ameoto
