// SPDX-License-Identifier: GPL-3.0-or-later
// The incompressible added mass of a thin screen by vortex rings (air_loading.hpp has the method).
#include "engine/models/air_loading.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "engine/core/physical_constants.hpp"
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
    Eigen::VectorXd rate(n);
    for (Eigen::Index m = 0; m < n; ++m) {
        const double w = modes.omega[m], k = w / speed_of_sound;
        double integral = 0.0;
        for (std::size_t a = 0; a < mu.size(); ++a) {
            const double sin_theta = std::sqrt(std::max(0.0, 1.0 - mu[a] * mu[a]));
            for (int b = 0; b < azimuth_points; ++b) {
                const double psi = 2.0 * constants::pi * b / azimuth_points;
                const double kx = k * sin_theta * std::cos(psi), ky = k * sin_theta * std::sin(psi);
                double re = 0.0, im = 0.0;
                for (Eigen::Index i = 0; i < source.rows(); ++i) {
                    const Point2 y = air.centroid[static_cast<std::size_t>(i)];
                    const double phase = kx * y.x + ky * y.y;
                    re += source(i, m) * std::cos(phase);
                    im += source(i, m) * std::sin(phase);
                }
                integral += weight[a] * (2.0 * constants::pi / azimuth_points) * mu[a] * mu[a] * (re * re + im * im);
            }
        }
        integral *= 2.0;   // both half-spaces
        rate[m] = k * k * w * w / (32.0 * constants::pi * constants::pi * air_density * speed_of_sound) * integral;
    }
    return rate;
}

}  // namespace ameoto
