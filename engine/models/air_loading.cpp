// SPDX-License-Identifier: GPL-3.0-or-later
// The incompressible added mass of a thin screen by vortex rings (air_loading.hpp has the method).
#include "engine/models/air_loading.hpp"

#include <cmath>
#include <algorithm>
#include <complex>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "engine/core/phase_sincos.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading_sectors.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto {

namespace {

struct Segment {
    Point2 a, b;
};

// Each cell's boundary as straight runs of square edges, oriented counter-clockwise round the cell.
std::vector<std::vector<Segment>> cell_boundaries(const ScreenSampling& s) {
    std::vector<std::vector<Segment>> rings(static_cast<std::size_t>(s.cells));
    auto owner = [&](int i, int j) {
        if (i < 0 || j < 0 || i >= s.nx || j >= s.ny) return -1;
        return s.owner[static_cast<std::size_t>(j * s.nx + i)];
    };
    auto x_at = [&](int i) { return s.origin.x + i * s.side; };
    auto y_at = [&](int j) { return s.origin.y + j * s.side; };
    // Horizontal grid line j (y = y_at(j)) between square (i, j - 1) below and (i, j) above: the square
    // above runs its bottom edge towards +x, the one below its top edge towards -x. Runs of equal pairs
    // merge into one segment each.
    for (int j = 0; j <= s.ny; ++j) {
        int i = 0;
        while (i < s.nx) {
            const int up = owner(i, j), down = owner(i, j - 1);
            int e = i + 1;
            while (e < s.nx && owner(e, j) == up && owner(e, j - 1) == down) ++e;
            if (up != down) {
                const Point2 left{x_at(i), y_at(j)}, right{x_at(e), y_at(j)};
                if (up >= 0) rings[static_cast<std::size_t>(up)].push_back({left, right});
                if (down >= 0) rings[static_cast<std::size_t>(down)].push_back({right, left});
            }
            i = e;
        }
    }
    // Vertical grid line i (x = x_at(i)) between (i - 1, j) on the left and (i, j) on the right: the right
    // square runs its left edge towards -y, the left one its right edge towards +y.
    for (int i = 0; i <= s.nx; ++i) {
        int j = 0;
        while (j < s.ny) {
            const int right = owner(i, j), left = owner(i - 1, j);
            int e = j + 1;
            while (e < s.ny && owner(i, e) == right && owner(i - 1, e) == left) ++e;
            if (right != left) {
                const Point2 low{x_at(i), y_at(j)}, high{x_at(i), y_at(e)};
                if (right >= 0) rings[static_cast<std::size_t>(right)].push_back({high, low});
                if (left >= 0) rings[static_cast<std::size_t>(left)].push_back({low, high});
            }
            j = e;
        }
    }
    return rings;
}

}  // namespace

double ring_segment_velocity(Point2 p, Point2 a, Point2 b) {
    // Biot-Savart for a straight vortex segment of unit circulation (Katz & Plotkin eq. 10.115):
    //   v = (1 / 4 pi) (r1 x r2) / |r1 x r2|^2  r0 . (r1 / |r1| - r2 / |r2|),
    // r0 = b - a, r1 = p - a, r2 = p - b. In the segment's plane only the z component is left, and
    // (r1 x r2)_z / |r1 x r2|^2 = 1 / (r1 x r2)_z.
    const double r1x = p.x - a.x, r1y = p.y - a.y, r2x = p.x - b.x, r2y = p.y - b.y;
    const double r0x = b.x - a.x, r0y = b.y - a.y;
    const double cross = r1x * r2y - r1y * r2x;
    const double l1 = std::hypot(r1x, r1y), l2 = std::hypot(r2x, r2y);
    const double length2 = r0x * r0x + r0y * r0y;
    // On the segment's line (outside it) the exact velocity is 0; on the segment itself it is singular,
    // which no collocation point meets.
    if (std::abs(cross) <= 1e-12 * length2 || l1 == 0.0 || l2 == 0.0) return 0.0;
    const double along = r0x * (r1x / l1 - r2x / l2) + r0y * (r1y / l1 - r2y / l2);
    return along / (4.0 * constants::pi * cross);
}

ScreenSampling sample_screen(Point2 lo, Point2 hi, double h, int cells, const std::function<int(Point2)>& owner) {
    if (!(h > 0.0)) throw std::invalid_argument("sample_screen: the square side must be positive");
    if (!(hi.x > lo.x && hi.y > lo.y)) throw std::invalid_argument("sample_screen: the box is empty");
    if (cells < 1) throw std::invalid_argument("sample_screen: no cells");
    ScreenSampling s;
    s.origin = lo;
    s.side = h;
    s.nx = static_cast<int>(std::ceil((hi.x - lo.x) / h));
    s.ny = static_cast<int>(std::ceil((hi.y - lo.y) / h));
    s.cells = cells;
    s.owner.assign(static_cast<std::size_t>(s.nx) * static_cast<std::size_t>(s.ny), -1);
    std::vector<int> count(static_cast<std::size_t>(cells), 0);
    for (int j = 0; j < s.ny; ++j) {
        for (int i = 0; i < s.nx; ++i) {
            const int o = owner({lo.x + (i + 0.5) * h, lo.y + (j + 0.5) * h});
            if (o < -1 || o >= cells) throw std::invalid_argument("sample_screen: owner " + std::to_string(o) + " out of range");
            s.owner[static_cast<std::size_t>(j * s.nx + i)] = o;
            if (o >= 0) ++count[static_cast<std::size_t>(o)];
        }
    }
    for (int c = 0; c < cells; ++c)
        if (count[static_cast<std::size_t>(c)] == 0)
            throw std::runtime_error("sample_screen: cell " + std::to_string(c) + " owns no square; use smaller squares");
    return s;
}

AddedMass screen_added_mass(const ScreenSampling& s, double air_density) {
    const int n = s.cells;
    AddedMass out;
    out.area = Eigen::VectorXd::Zero(n);
    out.centroid.assign(static_cast<std::size_t>(n), Point2{});
    const double a = s.side * s.side;
    for (int j = 0; j < s.ny; ++j) {
        for (int i = 0; i < s.nx; ++i) {
            const int o = s.owner[static_cast<std::size_t>(j * s.nx + i)];
            if (o < 0) continue;
            out.area[o] += a;
            out.centroid[static_cast<std::size_t>(o)].x += a * (s.origin.x + (i + 0.5) * s.side);
            out.centroid[static_cast<std::size_t>(o)].y += a * (s.origin.y + (j + 0.5) * s.side);
        }
    }
    for (int c = 0; c < n; ++c) {
        out.centroid[static_cast<std::size_t>(c)].x /= out.area[c];
        out.centroid[static_cast<std::size_t>(c)].y /= out.area[c];
    }
    const auto rings = cell_boundaries(s);
    Eigen::MatrixXd g(n, n);
    for (int col = 0; col < n; ++col) {
        const auto& ring = rings[static_cast<std::size_t>(col)];
        for (int row = 0; row < n; ++row) {
            const Point2 p = out.centroid[static_cast<std::size_t>(row)];
            double w = 0.0;
            for (const Segment& seg : ring) w += ring_segment_velocity(p, seg.a, seg.b);
            g(row, col) = w;
        }
    }
    // M_a = rho0 diag(A) G^-1 (header), symmetrised.
    const Eigen::MatrixXd m = air_density * out.area.asDiagonal() * g.partialPivLu().inverse();
    out.matrix = 0.5 * (m + m.transpose());
    return out;
}

AddedMass canopy_added_mass(const Canopy& canopy, double square_side_m, double air_density) {
    const double r = canopy.geometry().radius_m;
    const int nodes = canopy.nodes_per_panel();
    const auto owner = [&](Point2 p) {
        const CanopyHit hit = canopy.locate(p.x, p.y);
        return hit.panel < 0 ? -1 : hit.panel * nodes + hit.node;
    };
    const ScreenSampling s = sample_screen({-r, -r}, {r, r}, square_side_m, canopy.panel_count() * nodes, owner);
    return screen_added_mass(s, air_density);
}

namespace {

using namespace air_sectors;

struct SectorMass {
    std::vector<Eigen::MatrixXd> block;   // [d]: the air's mass of panel p's nodes on panel p + d's, kg
    Eigen::VectorXd area;                 // m^2 per node of a panel
    std::vector<Point2> centroid;         // panel 0's nodes
};

// One sampling level: the canopy's air mass as the N blocks of its block-circulant matrix.
SectorMass sector_mass(const Canopy& canopy, const std::vector<SectorCell>& cells, const std::vector<SectorElement>& elements,
                       double air_density) {
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    const int n = static_cast<int>(elements.size());
    SectorMass out;
    out.area = Eigen::VectorXd::Zero(nodes);
    out.centroid.assign(static_cast<std::size_t>(nodes), Point2{});
    Eigen::MatrixXd owner = Eigen::MatrixXd::Zero(n, nodes);   // P0: node velocities -> element velocities
    Eigen::VectorXd area(n);
    for (int c = 0; c < n; ++c) {
        const SectorElement& cell = elements[static_cast<std::size_t>(c)];
        owner(c, cell.node) = 1.0;
        area[c] = cell.area;
        out.area[cell.node] += cell.area;
        out.centroid[static_cast<std::size_t>(cell.node)].x += cell.area * cell.centroid.x;
        out.centroid[static_cast<std::size_t>(cell.node)].y += cell.area * cell.centroid.y;
    }
    for (int k = 0; k < nodes; ++k) {
        if (!(out.area[k] > 0.0))
            throw std::runtime_error("canopy_added_mass: node " + std::to_string(k) + " owns no sub-cell; use more rows");
        out.centroid[static_cast<std::size_t>(k)].x /= out.area[k];
        out.centroid[static_cast<std::size_t>(k)].y /= out.area[k];
    }
    // g_d(i, k): the velocity at panel 0's cell i from the unit ring of panel d's cell k (panel d is panel
    // 0 turned by 2 pi d / N, its cells numbered alike). The whole canopy's G is block circulant,
    // G[(p, i), (q, k)] = g_(q - p mod N)(i, k), so on the panels' Fourier modes (x_q = e^(i theta q) y,
    // theta = 2 pi m / N) it is G_m = sum_d g_d e^(i theta d): N solves of one panel's size in place of
    // one of N panels' (Davis, Circulant Matrices, section 5.6).
    const std::vector<Eigen::MatrixXd> g = ring_velocities(canopy, cells, elements);
    // Per Fourier mode m: H_m = rho0 P0' diag(A) G_m^-1 P0 (the header's M_a, seen on the nodes: a node's
    // force is its cells' sum); H_(N-m) = conj(H_m), so m = 0..N/2 suffice. Then the blocks
    // M_d = M[(p, q = p + d)] = (1 / N) sum_m e^(-i theta_m d) H_m (real).
    const Eigen::MatrixXd weighted_owner = owner.transpose() * area.asDiagonal();
    out.block.assign(static_cast<std::size_t>(panels), Eigen::MatrixXd::Zero(nodes, nodes));
    for (int m = 0; m <= panels / 2; ++m) {
        const double theta = 2.0 * constants::pi * m / panels;
        Eigen::MatrixXcd gm = Eigen::MatrixXcd::Zero(n, n);
        for (int d = 0; d < panels; ++d) gm += std::polar(1.0, theta * d) * g[static_cast<std::size_t>(d)].cast<std::complex<double>>();
        const Eigen::MatrixXcd h = air_density * weighted_owner.cast<std::complex<double>>() *
                                   gm.partialPivLu().solve(owner.cast<std::complex<double>>());
        const double weight = (m == 0 || 2 * m == panels) ? 1.0 : 2.0;   // m and N - m together
        for (int d = 0; d < panels; ++d)
            out.block[static_cast<std::size_t>(d)] += weight / panels * (std::polar(1.0, -theta * d) * h).real();
    }
    return out;
}

// The whole canopy's matrix from its circulant blocks (block (p, q) = blocks[q - p mod N]), symmetrised.
Eigen::MatrixXd assemble_circulant(const std::vector<Eigen::MatrixXd>& blocks, int panels, int nodes) {
    Eigen::MatrixXd m(panels * nodes, panels * nodes);
    for (int p = 0; p < panels; ++p)
        for (int q = 0; q < panels; ++q)
            m.block(p * nodes, q * nodes, nodes, nodes) = blocks[static_cast<std::size_t>((q - p + panels) % panels)];
    return 0.5 * (m + m.transpose());
}

bool air_mass_positive_definite(const Eigen::MatrixXd& m) { return Eigen::LLT<Eigen::MatrixXd>(m).info() == Eigen::Success; }

}  // namespace

AddedMass canopy_added_mass(const Canopy& canopy, double air_density, const CanopyAirMassOptions& options) {
    if (options.rows < 2 || options.rows % 2) throw std::invalid_argument("canopy_added_mass: an even number of rows, at least 2");
    if (!(air_density > 0.0)) throw std::invalid_argument("canopy_added_mass: the air's density must be positive");
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    const std::vector<SectorCell> cells = sector_cells(canopy, options.rows);
    SectorMass fine = sector_mass(canopy, cells, single_elements(cells), air_density);
    if (options.extrapolate) {
        // Richardson in the cell size h ~ 1 / rows: M(h) = M + c h + O(h^2), so from rows r1 < r2
        // M = (r2 M(r2) - r1 M(r1)) / (r2 - r1) (the disc's error falls as h: the header).
        const SectorMass coarse = sector_mass(canopy, cells, grouped_elements(cells, nodes), air_density);
        const double r2 = options.rows, r1 = 0.5 * options.rows;
        std::vector<Eigen::MatrixXd> extrapolated(fine.block.size());
        for (int d = 0; d < panels; ++d)
            extrapolated[static_cast<std::size_t>(d)] =
                (r2 * fine.block[static_cast<std::size_t>(d)] - r1 * coarse.block[static_cast<std::size_t>(d)]) / (r2 - r1);
        // The two levels' node regions are staircased differently (a node's share of cells moves by up
        // to a cell at each level, not smoothly in h): where that makes the extrapolated mass indefinite
        // (rows 28 / 14 and 32 / 16 on the default canopy; 24 / 12, 40 / 20 and 56 / 28 are fine and agree
        // to 0.6 % on the lowest modes), the finer level alone is kept, with its O(h) error.
        if (air_mass_positive_definite(assemble_circulant(extrapolated, panels, nodes))) fine.block = std::move(extrapolated);
    }
    AddedMass out;
    const int total = panels * nodes;
    out.rotational_order = panels;   // panel_azimuth(p) = 2 pi p / N, the centroids turned below
    out.matrix = assemble_circulant(fine.block, panels, nodes);
    out.area.resize(total);
    out.centroid.resize(static_cast<std::size_t>(total));
    for (int p = 0; p < panels; ++p) {
        const double turn = canopy.panel_azimuth(p) - canopy.panel_azimuth(0);
        const double ct = std::cos(turn), st = std::sin(turn);
        for (int k = 0; k < nodes; ++k) {
            const Point2 c = fine.centroid[static_cast<std::size_t>(k)];
            out.area[p * nodes + k] = fine.area[k];
            out.centroid[static_cast<std::size_t>(p * nodes + k)] = {ct * c.x - st * c.y, st * c.x + ct * c.y};
        }
    }
    return out;
}

AirLoadedModes air_loaded_modes(const Canopy& canopy, const AddedMass& air) {
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel(), n = panels * nodes;
    if (air.matrix.rows() != n || air.matrix.cols() != n)
        throw std::invalid_argument("air_loaded_modes: the added mass is not the canopy's (" + std::to_string(air.matrix.rows()) +
                                    " cells, " + std::to_string(n) + " nodes)");
    // The panels are one body copied (canopy.hpp): one panel's K and C, placed on the diagonal.
    const auto& arrays = canopy.panel(0).network.arrays();
    const Eigen::MatrixXd kp = Eigen::MatrixXd(arrays.stiffness_matrix());
    const Eigen::MatrixXd cp = Eigen::MatrixXd(arrays.damping_matrix());
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n), c = Eigen::MatrixXd::Zero(n, n), m = air.matrix;
    for (int p = 0; p < panels; ++p) {
        k.block(p * nodes, p * nodes, nodes, nodes) = kp;
        c.block(p * nodes, p * nodes, nodes, nodes) = cp;
        for (int i = 0; i < nodes; ++i) m(p * nodes + i, p * nodes + i) += arrays.mass(static_cast<std::size_t>(i));
    }
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k, m);
    if (solver.info() != Eigen::Success) throw std::runtime_error("air_loaded_modes: eigen-solve failed");
    AirLoadedModes out;
    out.omega = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    out.shapes = solver.eigenvectors();
    out.damping_rate = 0.5 * (out.shapes.transpose() * c * out.shapes).diagonal();
    return out;
}

Eigen::VectorXd radiation_damping(const AirLoadedModes& modes, const AddedMass& air, double air_density,
                                  double speed_of_sound, int polar_points, int azimuth_points) {
    if (polar_points < 2 || azimuth_points < 4)
        throw std::invalid_argument("radiation_damping: at least 2 polar and 4 azimuth points");
    const Eigen::Index n = modes.omega.size();
    // Gauss-Legendre nodes and weights on mu = cos(theta) in [0, 1] (Newton on P_n, Abramowitz & Stegun 25.4.29).
    std::vector<double> mu(static_cast<std::size_t>(polar_points)), weight(mu.size());
    for (int k = 0; k < polar_points; ++k) {
        double x = std::cos(constants::pi * (k + 0.75) / (polar_points + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = x;
            for (int j = 2; j <= polar_points; ++j) {
                const double p2 = ((2 * j - 1) * x * p1 - (j - 1) * p0) / j;
                p0 = p1;
                p1 = p2;
            }
            dp = polar_points * (x * p1 - p0) / (x * x - 1.0);
            const double step = p1 / dp;
            x -= step;
            if (std::abs(step) < 1e-15) break;
        }
        mu[static_cast<std::size_t>(k)] = 0.5 * (x + 1.0);   // [-1, 1] -> [0, 1]
        weight[static_cast<std::size_t>(k)] = 1.0 / ((1.0 - x * x) * dp * dp);   // 2 / ((1 - x^2) P'^2), halved
    }
    const Eigen::MatrixXd source = air.matrix * modes.shapes;   // (M_a phi)_i per mode: N per unit q''
    const Eigen::Index cells = source.rows();
    // The sines and cosines of the phases were nearly all of a scene's build in air: two symmetries cut them,
    // and phase_sincos takes each pair in a vectorised loop (a third of two libm calls).
    // - Turns: with N sectors and an azimuth count divisible by N, the direction psi + 2 pi q / N sees
    //   cell (p, i) with the phase psi sees cell (p - q, i) with. So one sector's directions' phasors,
    //   each paired with the sources of every turn q, give all the directions: N times fewer.
    // - Otherwise, the sources being real, psi + pi (every phase negated) gives the conjugate sum and the
    //   same power: with an even count the first half of the azimuths is summed, each twice.
    const int order = air.rotational_order;
    const bool turns = order > 1 && azimuth_points % order == 0 && cells % order == 0;
    const bool halves = !turns && azimuth_points % 2 == 0;
    const int azimuths_summed = turns ? azimuth_points / order : halves ? azimuth_points / 2 : azimuth_points;
    const int copies = turns ? order : 1;                 // directions each set of phasors serves
    const Eigen::Index sector = cells / copies;
    const double azimuth_weight = (halves ? 2.0 : 1.0) * 2.0 * constants::pi / azimuth_points;
    std::vector<double> cosines(static_cast<std::size_t>(cells)), sines(cosines.size());
    std::vector<double> centroid_x(cosines.size()), centroid_y(cosines.size());
    double reach = 0.0;   // m: the farthest centroid from the axis
    for (Eigen::Index i = 0; i < cells; ++i) {
        centroid_x[static_cast<std::size_t>(i)] = air.centroid[static_cast<std::size_t>(i)].x;
        centroid_y[static_cast<std::size_t>(i)] = air.centroid[static_cast<std::size_t>(i)].y;
        reach = std::max(reach, std::hypot(centroid_x[static_cast<std::size_t>(i)], centroid_y[static_cast<std::size_t>(i)]));
    }
    Eigen::VectorXd rate(n);
    for (Eigen::Index m = 0; m < n; ++m) {
        const double w = modes.omega[m], k = w / speed_of_sound;
        if (!(k * reach <= phase_sincos_limit))
            throw std::invalid_argument("radiation_damping: a mode's phases across the canopy exceed " + std::to_string(phase_sincos_limit) + " rad");
        double integral = 0.0;
        for (std::size_t a = 0; a < mu.size(); ++a) {
            const double sin_theta = std::sqrt(std::max(0.0, 1.0 - mu[a] * mu[a]));
            for (int b = 0; b < azimuths_summed; ++b) {
                const double psi = 2.0 * constants::pi * b / azimuth_points;
                const double kx = k * sin_theta * std::cos(psi), ky = k * sin_theta * std::sin(psi);
                // |phase| <= k reach: within phase_sincos's range for any canopy it can hear (checked
                // once per mode, above); a loop the compiler vectorises.
                for (std::size_t i = 0; i < cosines.size(); ++i)
                    phase_sincos(kx * centroid_x[i] + ky * centroid_y[i], sines[i], cosines[i]);
                const double* column = source.col(m).data();
                for (int q = 0; q < copies; ++q) {
                    // The direction psi + 2 pi q / N: cell j's phasor with the source of cell j turned by q
                    // sectors, cell (j + q sector) mod cells; in two runs, so no division per cell.
                    const Eigen::Index wrap = cells - q * sector;
                    double re = 0.0, im = 0.0;
                    for (Eigen::Index j = 0; j < wrap; ++j) {
                        re += column[j + q * sector] * cosines[static_cast<std::size_t>(j)];
                        im += column[j + q * sector] * sines[static_cast<std::size_t>(j)];
                    }
                    for (Eigen::Index j = wrap; j < cells; ++j) {
                        re += column[j - wrap] * cosines[static_cast<std::size_t>(j)];
                        im += column[j - wrap] * sines[static_cast<std::size_t>(j)];
                    }
                    integral += weight[a] * azimuth_weight * mu[a] * mu[a] * (re * re + im * im);
                }
            }
        }
        integral *= 2.0;   // both half-spaces
        rate[m] = k * k * w * w / (32.0 * constants::pi * constants::pi * air_density * speed_of_sound) * integral;
    }
    return rate;
}

}  // namespace ameoto
