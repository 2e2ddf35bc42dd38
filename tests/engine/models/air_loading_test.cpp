// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/air_loading: the incompressible added mass of a thin screen in free air.
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Eigenvalues>

#include "engine/core/modal_decomposition.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/membrane.hpp"
#include "engine/reference/canopy_in_air.hpp"

using ameoto::AddedMass;
using ameoto::Point2;
using ameoto::PolygonEdge;

namespace {

constexpr double kAirTestPi = ameoto::constants::pi;
constexpr double kAirTestRho = ameoto::constants::air_density;

std::vector<PolygonEdge> circle(double radius, int sides) {
    std::vector<PolygonEdge> p;
    for (int k = 0; k < sides; ++k) {
        const double t = 2.0 * kAirTestPi * k / sides;
        p.push_back({{radius * std::cos(t), radius * std::sin(t)}, true});
    }
    return p;
}

// A disc of radius a cut into the cells of a triangular lattice's nodes (each square to its nearest node).
AddedMass disc_added_mass(double a, const ameoto::TriangularLattice& lattice, double square) {
    const auto owner = [&](Point2 p) {
        if (p.x * p.x + p.y * p.y >= a * a) return -1;
        return lattice.nearest_node_brute_force(p);
    };
    const auto s = ameoto::sample_screen({-a, -a}, {a, a}, square, static_cast<int>(lattice.nodes.size()), owner);
    return ameoto::screen_added_mass(s, kAirTestRho);
}

// The dominant angular order of a mode shape over nodes at angles theta: argmax_m |sum phi e^{-i m theta} r|.
int angular_order(const Eigen::VectorXd& phi, const std::vector<Point2>& nodes, int max_order) {
    int best = 0;
    double best_power = -1.0;
    double norm = 0.0;
    for (Eigen::Index i = 0; i < phi.size(); ++i) norm += phi[i] * phi[i];
    for (int m = 0; m <= max_order; ++m) {
        double re = 0.0, im = 0.0;
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            const double t = std::atan2(nodes[i].y, nodes[i].x), r = std::hypot(nodes[i].x, nodes[i].y);
            re += phi[static_cast<Eigen::Index>(i)] * r * std::cos(m * t);
            im += phi[static_cast<Eigen::Index>(i)] * r * std::sin(m * t);
        }
        const double power = (re * re + im * im) / (m == 0 ? 2.0 : 1.0) / norm;
        if (power > best_power) {
            best_power = power;
            best = m;
        }
    }
    return best;
}

// The lowest frequency (Hz) of each angular order 0..orders-1 among the modes of (K, M).
std::vector<double> lowest_per_order(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m, const std::vector<Point2>& nodes,
                                     int orders) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k, m);
    REQUIRE(solver.info() == Eigen::Success);
    std::vector<double> f(static_cast<std::size_t>(orders), 0.0);
    for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j) {
        const int order = angular_order(solver.eigenvectors().col(j), nodes, orders + 2);
        if (order < orders && f[static_cast<std::size_t>(order)] == 0.0)
            f[static_cast<std::size_t>(order)] = std::sqrt(std::max(0.0, solver.eigenvalues()[j])) / (2.0 * kAirTestPi);
    }
    return f;
}

}  // namespace

TEST_CASE("air loading: a vortex segment's in-plane velocity is Biot-Savart's") {
    // A point at distance d from the middle of a segment of length 2 L: v = (1 / 4 pi d) 2 L / sqrt(L^2 + d^2),
    // along +z for a point on the left of a -> b (counter-clockwise circulation round it).
    const double d = 0.3, l = 0.4;
    const double v = ameoto::ring_segment_velocity({0.0, d}, {-l, 0.0}, {l, 0.0});
    CHECK(v == ameoto::test::relative(2.0 * l / std::sqrt(l * l + d * d) / (4.0 * kAirTestPi * d)).epsilon(1e-12));
    CHECK(ameoto::ring_segment_velocity({0.0, -d}, {-l, 0.0}, {l, 0.0}) == ameoto::test::relative(-v).epsilon(1e-12));
    CHECK(ameoto::ring_segment_velocity({2.0, 0.0}, {-l, 0.0}, {l, 0.0}) == 0.0);   // on the line, outside
}

TEST_CASE("air loading: a disc's added mass converges to Lamb's (8/3) rho0 a^3") {
    // Lamb, Hydrodynamics (6th ed.), section 108: a circular disc moving broadside in unbounded fluid
    // carries (8/3) rho a^3 (both faces). Read in Martin, J. Eng. Math. 33:421 (1998); acoustics.md s.1.
    // Rigid cells with their rings' velocity matched at the centroids over-estimate it by an error of
    // order h, the cells' size (6.3 % for 363 cells, 4.4 % for 721): held here within 7 % at the
    // umbrella's cell density and, extrapolated to h -> 0 from two spacings (Richardson, error ~ h),
    // within 2 %.
    const double a = 0.25;
    const double lamb = 8.0 / 3.0 * kAirTestRho * a * a * a;
    double total[2] = {0.0, 0.0};
    const double spacing[2] = {0.025, 0.025 / std::sqrt(2.0)};
    AddedMass added;
    for (int level = 0; level < 2; ++level) {
        const auto lattice = ameoto::build_triangular_lattice(circle(a, 64), spacing[level]);
        added = disc_added_mass(a, lattice, spacing[level] / 8.0);
        total[level] = added.matrix.sum();   // 1' M_a 1: the force for a uniform unit acceleration
        std::printf("disc a = %.2f m, %zu cells: added mass %.5f kg, Lamb %.5f kg (%+.2f %%)\n", a, lattice.nodes.size(),
                    total[level], lamb, 100.0 * (total[level] / lamb - 1.0));
    }
    const double extrapolated = (total[1] * spacing[0] - total[0] * spacing[1]) / (spacing[0] - spacing[1]);
    std::printf("  extrapolated to h -> 0: %.5f kg (%+.2f %%)\n", extrapolated, 100.0 * (extrapolated / lamb - 1.0));
    CHECK(total[0] > total[1]);   // it converges from above
    CHECK(std::abs(total[0] / lamb - 1.0) < 0.07);
    CHECK(std::abs(extrapolated / lamb - 1.0) < 0.02);
    // The matrix is positive definite (kinetic energy of the air is positive for any motion).
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(added.matrix);
    CHECK(eig.eigenvalues().minCoeff() > 0.0);
    // The pressure jump of uniform motion follows Lamb's sqrt(a^2 - r^2) profile: the force per area at
    // r = a / 2 over that at the centre is sqrt(3) / 2 (within 5 %: a ring of cells at each radius).
    const Eigen::VectorXd force = added.matrix * Eigen::VectorXd::Ones(added.area.size());
    double centre = 0.0, half = 0.0, nc = 0.0, nh = 0.0;
    for (Eigen::Index i = 0; i < force.size(); ++i) {
        const double r = std::hypot(added.centroid[static_cast<std::size_t>(i)].x, added.centroid[static_cast<std::size_t>(i)].y);
        const double per_area = force[i] / added.area[i];
        if (r < 0.15 * a) centre += per_area, ++nc;
        if (std::abs(r - 0.5 * a) < 0.05 * a) half += per_area, ++nh;
    }
    REQUIRE(nc > 0);
    REQUIRE(nh > 0);
    CHECK((half / nh) / (centre / nc) == ameoto::test::relative(std::sqrt(3.0) / 2.0).epsilon(0.05));
}

TEST_CASE("air loading: the timpani head's modes in free air (Christian et al. 1984)") {
    // Christian, Davis, Tubis, Anderson, Mills & Rossing, J. Acoust. Soc. Am. 76(5):1336 (1984): a = 0.328 m,
    // s = 0.2653 kg/m^2, T = 3990 N/m. Measured without the kettle (Rossing 1982, acoustics.md s.1): (m,1) for
    // m = 2..5 relative to (1,1): 1.48, 1.92, 2.36, 2.78. The incompressible screen gives 3-5 % less (the same at
    // 250, 500 and 1000 masses, so not the lattice's resolution): held within 6 %, and each ratio raised by the
    // air above the vacuum's. (1,1) falls to 0.64-0.76 of its vacuum frequency (the diagonal estimate's
    // 0.71; a bound, not a target). The vacuum ratios are Bessel's.
    const double a = 0.328;
    const auto material = ameoto::MembraneMaterial::custom("timpani", 0.2653, 3990.0, 0.0, 0.0);
    const auto membrane = ameoto::build_membrane(circle(a, 64), 500, material, 1.0 / 48000.0);
    const auto& nodes = membrane.lattice.nodes;
    const auto& arrays = membrane.network.arrays();
    const Eigen::MatrixXd k = Eigen::MatrixXd(arrays.stiffness_matrix());
    Eigen::VectorXd m(static_cast<Eigen::Index>(nodes.size()));
    for (std::size_t i = 0; i < nodes.size(); ++i) m[static_cast<Eigen::Index>(i)] = arrays.mass(i);
    const auto owner = [&](Point2 p) { return p.x * p.x + p.y * p.y >= a * a ? -1 : membrane.lattice.nearest_node_brute_force(p); };
    const auto s = ameoto::sample_screen({-a, -a}, {a, a}, membrane.lattice.spacing / 7.0, static_cast<int>(nodes.size()), owner);
    const AddedMass added = ameoto::screen_added_mass(s, kAirTestRho);

    const Eigen::MatrixXd vacuum_m = m.asDiagonal();
    const auto vac = lowest_per_order(k, vacuum_m, nodes, 6);
    const auto air = lowest_per_order(k, Eigen::MatrixXd(vacuum_m + added.matrix), nodes, 6);
    const double bessel[] = {1.0, 1.34, 1.66, 1.98, 2.29};
    const double measured[] = {1.0, 1.48, 1.92, 2.36, 2.78};
    std::printf("timpani, %zu masses: (0,1) %.1f -> %.1f Hz, (1,1) %.1f -> %.1f Hz (x %.3f)\n", nodes.size(), vac[0], air[0],
                vac[1], air[1], air[1] / vac[1]);
    for (int order = 1; order <= 5; ++order) {
        const double rv = vac[static_cast<std::size_t>(order)] / vac[1], ra = air[static_cast<std::size_t>(order)] / air[1];
        std::printf("  (%d,1): vacuum %.3f (Bessel %.2f), air %.3f (measured %.2f, %+.1f %%)\n", order, rv, bessel[order - 1], ra,
                    measured[order - 1], 100.0 * (ra / measured[order - 1] - 1.0));
        CHECK(rv == ameoto::test::relative(bessel[order - 1]).epsilon(0.02));   // the lattice itself
        CHECK(ra == ameoto::test::relative(measured[order - 1]).epsilon(0.06));
        if (order > 1) CHECK(ra > rv + 0.05);
    }
    CHECK(air[1] / vac[1] > 0.64);
    CHECK(air[1] / vac[1] < 0.76);
}

TEST_CASE("air loading: the umbrella's lowest modes fall into 70-90 Hz in air") {
    // acoustics.md s.1: an air-loaded 0.5 m nylon panel's lowest mode near 70-90 Hz (diagonal estimates:
    // 68 Hz baffled on two faces, about 90 unbaffled, for a circular panel; 77 Hz for a square one).
    const double dt = 1.0 / 48000.0;
    const ameoto::Canopy canopy({}, ameoto::MembraneMaterial::nylon_canopy(), dt);
    const AddedMass added = ameoto::canopy_added_mass(canopy, 0.004, kAirTestRho);
    const int n = canopy.panel_count() * canopy.nodes_per_panel();
    REQUIRE(added.matrix.rows() == n);
    const auto vac = ameoto::decompose_modes(canopy.panel(0).network.arrays());
    const ameoto::AirLoadedModes air = ameoto::air_loaded_modes(canopy, added);
    const double f_vac = vac.omega[0] / (2 * kAirTestPi), f_air = air.omega[0] / (2 * kAirTestPi);
    std::printf("umbrella: lowest mode %.1f Hz in vacuum, %.1f Hz in air; air's mass on the first: %.2f x the fabric's\n", f_vac,
                f_air, (f_vac * f_vac) / (f_air * f_air) - 1.0);
    ameoto::AirLoadedModes lowest{air.omega.head(12), air.shapes.leftCols(12), air.damping_rate.head(12)};
    const Eigen::VectorXd radiation =
        ameoto::radiation_damping(lowest, added, kAirTestRho, ameoto::constants::speed_of_sound_air);
    // The panels moving together (modes 0 and 8) carry the canopy's net force: they radiate as a dipole
    // and lose more to the air than to the fabric; modes with nodal lines between the panels radiate as
    // higher multipoles, orders of magnitude less.
    CHECK(radiation[0] > air.damping_rate[0]);
    CHECK(radiation[8] > air.damping_rate[8]);
    for (int j = 1; j < 8; ++j) CHECK(radiation[j] < 0.2 * radiation[0]);
    for (int j = 0; j < 12; ++j)
        std::printf("  canopy mode %d in air: %.1f Hz, decay %.1f /s by the fabric, %.1f /s by radiation\n", j,
                    air.omega[j] / (2 * kAirTestPi), air.damping_rate[j], radiation[j]);
    // Mass-normalised over M + M_a; and the air lengthens every mode's ring: the material's alpha M
    // term is the same, its beta K term falls with omega^2.
    Eigen::MatrixXd m = added.matrix;
    for (int i = 0; i < n; ++i) m(i, i) += canopy.panel(0).network.arrays().mass(static_cast<std::size_t>(i % canopy.nodes_per_panel()));
    const Eigen::MatrixXd unit = air.shapes.transpose() * m * air.shapes;
    CHECK((unit - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff() < 1e-9);
    CHECK(air.damping_rate.minCoeff() > 0.0);
    CHECK(air.damping_rate[0] < vac.damping_rate[0]);
    CHECK(f_air > 60.0);
    CHECK(f_air < 100.0);

    // The sector shortcut (one sector's phasors for every turn of the direction) against every direction
    // summed on its own, on the canopy's air mass as the scene builds it (its sectors: the squares above
    // are not turned copies, so that mass takes the half-circle path): the same damping to rounding.
    const AddedMass sectors = ameoto::canopy_added_mass(canopy, kAirTestRho);
    REQUIRE(sectors.rotational_order == canopy.panel_count());
    const ameoto::AirLoadedModes in_air = ameoto::air_loaded_modes(canopy, sectors);
    const ameoto::AirLoadedModes first{in_air.omega.head(12), in_air.shapes.leftCols(12), in_air.damping_rate.head(12)};
    AddedMass unturned = sectors;
    unturned.rotational_order = 1;
    const Eigen::VectorXd turned = ameoto::radiation_damping(first, sectors, kAirTestRho, ameoto::constants::speed_of_sound_air);
    const Eigen::VectorXd direct = ameoto::radiation_damping(first, unturned, kAirTestRho, ameoto::constants::speed_of_sound_air);
    for (int j = 0; j < 12; ++j) CHECK(turned[j] == ameoto::test::relative(direct[j]).epsilon(1e-9));
    CHECK(turned[0] > in_air.damping_rate[0]);   // a real figure, not two zeros agreeing
}

TEST_CASE("air loading: a rigid disc's radiation damping is a point force's dipole power at small ka") {
    // A body moving with acceleration a puts the force m_a a on the air; at small ka it radiates as a point
    // force F: W = k^2 |F|^2 / (24 pi rho0 c) (Morse & Ingard, Theoretical Acoustics, 7.1; the dipole), so a
    // uniform mode of total mass M = m + m_a (phi = 1 / sqrt M) decays by s = W / 2E = k^2 w^2 m_a^2 / (24 pi rho0 c M).
    const double a = 0.1, c = ameoto::constants::speed_of_sound_air;
    const auto lattice = ameoto::build_triangular_lattice(circle(a, 48), 0.02);
    const AddedMass added = disc_added_mass(a, lattice, 0.02 / 6.0);
    const double ma = added.matrix.sum(), body = 0.01, total = body + ma;
    ameoto::AirLoadedModes mode;
    mode.shapes = Eigen::MatrixXd::Constant(added.area.size(), 1, 1.0 / std::sqrt(total));
    mode.damping_rate = Eigen::VectorXd::Zero(1);
    for (double ka : {0.02, 0.05}) {
        const double w = ka * c / a, k = ka / a;
        mode.omega = Eigen::VectorXd::Constant(1, w);
        const double s = ameoto::radiation_damping(mode, added, kAirTestRho, c)[0];
        const double expected = k * k * w * w * ma * ma / (24.0 * kAirTestPi * kAirTestRho * c * total);
        std::printf("disc a = %.2f m, ka %.2f: radiation decay %.4g /s, point dipole %.4g /s\n", a, ka, s, expected);
        CHECK(s == ameoto::test::relative(expected).epsilon(0.01));
    }
    // At ka = 2 the cells' phases across the disc cut the far field below the point dipole's.
    mode.omega = Eigen::VectorXd::Constant(1, 2.0 * c / a);
    const double s2 = ameoto::radiation_damping(mode, added, kAirTestRho, c)[0];
    const double point2 = std::pow(2.0 / a, 2) * std::pow(2.0 * c / a, 2) * ma * ma / (24.0 * kAirTestPi * kAirTestRho * c * total);
    CHECK(s2 < point2);
    CHECK(s2 > 0.2 * point2);
}

TEST_CASE("air loading: the umbrella's converged air mass is block circulant, positive definite and Lamb's at rigid motion") {
    const ameoto::Canopy canopy({}, ameoto::MembraneMaterial::nylon_canopy(), 1.0 / 48000.0);
    const int nodes = canopy.nodes_per_panel(), n = canopy.panel_count() * nodes;
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const AddedMass a = ameoto::canopy_added_mass(canopy, kAirTestRho);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    REQUIRE(a.matrix.rows() == n);
    CHECK((a.matrix - a.matrix.transpose()).cwiseAbs().maxCoeff() == 0.0);
    CHECK(Eigen::LLT<Eigen::MatrixXd>(a.matrix).info() == Eigen::Success);
    // The panels are one triangle turned: block (p, q) depends on q - p only.
    for (int p = 1; p < canopy.panel_count(); ++p)
        CHECK((a.matrix.block(p * nodes, ((p + 3) % 8) * nodes, nodes, nodes) - a.matrix.block(0, 3 * nodes, nodes, nodes))
                  .cwiseAbs()
                  .maxCoeff() < 1e-12 * a.matrix.cwiseAbs().maxCoeff());
    CHECK(a.area.sum() == ameoto::test::relative(canopy.area()).epsilon(1e-9));
    // Rigid motion: the octagon's added mass against Lamb's (8/3) rho0 a^3 for the disc of its area
    // (Hydrodynamics, section 108). The regular octagon is not a disc, so 2 % (the single-level
    // sampling at the same rows: +1.6 %; the one-ring-per-node sampling: +5.5 %).
    const double lamb = 8.0 / 3.0 * kAirTestRho * std::pow(canopy.area() / kAirTestPi, 1.5);
    const AddedMass single = ameoto::canopy_added_mass(canopy, kAirTestRho, ameoto::CanopyAirMassOptions{24, false});
    std::printf("umbrella's air mass (rows 24, extrapolated): built in %.2f s wall, %.2f s CPU; rigid %.4f kg, %+.2f %% of the equal-area disc's "
                "(rows 24 alone %+.2f %%)\n",
                took, cpu, a.matrix.sum(), 100.0 * (a.matrix.sum() / lamb - 1.0), 100.0 * (single.matrix.sum() / lamb - 1.0));
    CHECK(a.matrix.sum() == ameoto::test::relative(lamb).epsilon(0.02));
    const ameoto::AirLoadedModes air = ameoto::air_loaded_modes(canopy, a);
    std::printf("  the canopy's lowest modes in air:");
    for (int j = 0; j < 10; ++j) std::printf(" %.1f", air.omega[j] / (2 * kAirTestPi));
    std::printf(" Hz\n");
    CHECK(air.omega[0] / (2 * kAirTestPi) > 60.0);   // acoustics.md s.1: 70-90 Hz, a diagonal estimate
    CHECK(air.omega[0] / (2 * kAirTestPi) < 100.0);
    CHECK(a.matrix.sum() < single.matrix.sum());   // the O(h) over-estimate removed
    CHECK_THROWS_AS(ameoto::canopy_added_mass(canopy, kAirTestRho, ameoto::CanopyAirMassOptions{23, true}), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::canopy_added_mass(canopy, 0.0), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::canopy_added_mass(canopy, kAirTestRho, ameoto::CanopyAirMassOptions{4, true}), std::runtime_error);
}
