// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/air_canopy and dipole_radiation: the canopy's air-loaded modes run as
// resonators and heard as dipoles, held to the FDTD reference (engine/reference/canopy_in_air.hpp) in
// third-octave band levels, and the in-vacuum path left as it was.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_canopy.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/air_loading_in_phase.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/dipole_radiation.hpp"
#include "engine/models/drop_on_canopy.hpp"
#include "engine/reference/canopy_in_air.hpp"
#include "engine/reference/canopy_bands.hpp"
#include "engine/reference/screen_far_field.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/sanitizer_bounds.hpp"
#include "tests/support/timing_scale.hpp"
#include "tests/support/relative_approx.hpp"

namespace ameoto {

namespace {

constexpr double air_test_rate = 48000.0;

struct BandComparison {
    double worst_db = 0.0, median_db = 0.0;   // of |fast - reference| over the bands
    std::string table;
};

BandComparison compare_levels(const std::vector<reference::BandLevel>& a, const std::vector<reference::BandLevel>& b) {
    BandComparison c;
    std::vector<double> differences;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        const double d = a[i].level_db - b[i].level_db;
        c.worst_db = std::max(c.worst_db, std::abs(d));
        c.table += std::to_string(static_cast<int>(std::lround(a[i].centre_hz))) + ":" + std::to_string(d).substr(0, 5) + " ";
        differences.push_back(std::abs(d));
    }
    std::sort(differences.begin(), differences.end());
    if (!differences.empty()) c.median_db = differences[differences.size() / 2];
    return c;
}

// The canopy's modes with every panel's part alike (its Fourier block m = 0), ascending: written here
// independently of air_canopy.cpp's own test for them.
std::vector<int> in_phase_modes(const AirLoadedModes& all, int panels, int nodes) {
    std::vector<int> out;
    for (int k = 0; k < static_cast<int>(all.omega.size()); ++k) {
        const Eigen::VectorXd first = all.shapes.col(k).head(nodes);
        bool alike = true;
        for (int p = 1; p < panels; ++p) alike = alike && (all.shapes.col(k).segment(p * nodes, nodes) - first).norm() <= 1e-6 * first.norm();
        if (alike) out.push_back(k);
    }
    return out;
}

// The default canopy's modes in air as the server builds them, and with the incompressible poles and
// shapes (compressible_in_phase_ka 0), for telling what the in-phase block's compressible air moves.
struct TwoBuilds {
    Canopy canopy;
    std::shared_ptr<const AirCanopyModes> moved, plain;
};
TwoBuilds default_and_incompressible() {
    TwoBuilds b{Canopy(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / air_test_rate), nullptr, nullptr};
    b.moved = build_air_canopy_modes(b.canopy, 1.0 / air_test_rate);
    AirCanopyOptions incompressible;
    incompressible.compressible_in_phase_ka = 0.0;
    b.plain = build_air_canopy_modes(b.canopy, 1.0 / air_test_rate, incompressible);
    return b;
}

reference::CanopyInAirSetup cheap_reference() {
    reference::CanopyInAirSetup s;
    s.dx = 0.025;          // the cheap grid (about half the lattice's 4.5 cm spacing)
    s.margin_m = 0.1;      // air beyond the rim
    s.z_margin_m = 0.35;   // the default listener, 0.3 m under the canopy, inside the box
    s.duration_s = 0.1;
    return s;
}

}  // namespace

TEST_CASE("air canopy: the modes in air are mass-normalised resonators, contacts read through the shapes") {
    Canopy canopy(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / air_test_rate);
    const auto modes = build_air_canopy_modes(canopy, 1.0 / air_test_rate);
    REQUIRE(modes->modes == 400);
    REQUIRE(modes->modes_found == 400);
    MESSAGE("modes in air: " << modes->omega[0] / (2.0 * constants::pi) << " to " << modes->omega[modes->modes - 1] / (2.0 * constants::pi)
                              << " Hz; radiation damping of the lowest " << modes->radiation_rate[0] << " /s");
    // Air lowers every mode (the lattice's lowest is 217 Hz in vacuum: docs/canopy.md) and its highest
    // stays under the cutoff.
    CHECK(modes->omega[0] / (2.0 * constants::pi) < 150.0);
    CHECK(modes->omega[modes->modes - 1] / (2.0 * constants::pi) < 1200.0);
    canopy.set_air(modes);
    REQUIRE(canopy.in_air());
    // The contact mass is heavier than the node's own (the air moving with it).
    const double own = canopy.panel(0).network.mass(10);
    CHECK(canopy.contact_mass(0, 10) > own);
    // An impulse J on a node changes its velocity by J / contact mass at once (air_canopy.hpp), and
    // the motion read back through the shapes is finite and decays.
    double forces[8];
    const double j = 1e-4;
    canopy.apply_force({0, 10}, j * air_test_rate);
    canopy.step(forces);
    const double v0 = canopy.normal_velocity(0, 10);
    // The kick, then one step of the exact transition: within 2 % of J / m_contact (one step of ringing).
    CHECK(v0 == ameoto::test::relative(j / canopy.contact_mass(0, 10)).epsilon(0.02));
    const double e0 = canopy.panel_energy(0);
    for (int n = 0; n < 48000; ++n) canopy.step(forces);
    CHECK(canopy.panel_energy(0) < 1e-3 * e0);
    CHECK(canopy.panel_finite(0));
    // displacement_range bounds every node.
    canopy.apply_force({3, 20}, 5.0);
    for (int n = 0; n < 100; ++n) canopy.step(forces);
    const DisplacementRange range = canopy.displacement_range();
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            CHECK(canopy.displacement(k, i) <= range.highest);
            CHECK(canopy.displacement(k, i) >= range.lowest);
        }
}

TEST_CASE("air canopy: the in-phase modes up to ka 2 take their compressible poles, the block solved directly agrees") {
    const TwoBuilds builds = default_and_incompressible();
    const Canopy& canopy = builds.canopy;
    const auto& poles = builds.moved;
    const auto& plain = builds.plain;
    REQUIRE(poles->modes == plain->modes);
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    const double limit = 2.0 * constants::speed_of_sound_air / canopy.geometry().radius_m;   // ka = 2
    // The server's modes come from the same eigen-solve (air_loaded_modes): the in-phase ones below ka = 2
    // move, every other mode is as it was, bit for bit.
    const AddedMass added = canopy_added_mass(canopy, constants::air_density);
    const AirLoadedModes all = air_loaded_modes(canopy, added);
    const std::vector<int> in_phase = in_phase_modes(all, panels, nodes);
    REQUIRE(static_cast<int>(all.omega.size()) == plain->modes);
    for (int k = 0; k < plain->modes; ++k) {
        const bool alike = std::find(in_phase.begin(), in_phase.end(), k) != in_phase.end();
        const bool moved = alike && plain->omega[k] <= limit;
        if (!moved) {
            CHECK(poles->omega[k] == plain->omega[k]);
            CHECK(poles->rate[k] == plain->rate[k]);
        }
    }
    REQUIRE(in_phase.size() == static_cast<std::size_t>(nodes));   // block m = 0: one panel's worth
    REQUIRE(in_phase[0] == 0);
    // The lowest two: 84.6 -> 81.2 Hz and 168.7 -> 163.3 Hz (air_canopy.hpp), 3 to 5 % lower.
    int moved = 0;
    for (const int k : in_phase) {
        if (plain->omega[k] > limit) break;
        ++moved;
        const double shift = poles->omega[k] / plain->omega[k] - 1.0;
        MESSAGE("in-phase mode " << k << ": " << plain->omega[k] / (2.0 * constants::pi) << " Hz, " << plain->rate[k] << " /s -> "
                                 << poles->omega[k] / (2.0 * constants::pi) << " Hz, " << poles->rate[k] << " /s (radiation "
                                 << poles->radiation_rate[k] << " /s, the incompressible estimate's " << plain->radiation_rate[k] << ")");
        CHECK(shift < -0.03);
        CHECK(shift > -0.05);
        CHECK(poles->rate[k] > all.damping_rate[k] * 0.9);   // the material's, a little lighter, and the radiation's
    }
    CHECK(moved == 2);
    // Each pole against the block's driven response on the real axis (InPhaseAirMass at real frequencies,
    // which its own test holds to CanopyAirImpedanceBuilder's quadrature): the response of mode j's
    // coordinate to a force on it, |q_j(w)|, peaks at Re w_pole and falls to half its power Im w_pole either
    // side (a pole's Lorentzian; the other in-phase modes are 80 Hz away and more).
    const InPhaseAirMass series(canopy, constants::air_density, constants::speed_of_sound_air, limit * 1.05);
    const auto n = static_cast<Eigen::Index>(in_phase.size());
    Eigen::MatrixXcd psi(nodes, n);
    for (Eigen::Index j = 0; j < n; ++j) psi.col(j) = all.shapes.col(in_phase[static_cast<std::size_t>(j)]).head(nodes).cast<std::complex<double>>();
    for (int j = 0; j < moved; ++j) {
        const int mode = in_phase[static_cast<std::size_t>(j)];
        const auto response = [&](double w) {
            using cd = std::complex<double>;
            Eigen::MatrixXcd t = -w * w * (Eigen::MatrixXcd::Identity(n, n) + static_cast<double>(panels) * (psi.transpose() * series.change_at(w) * psi));
            for (Eigen::Index k = 0; k < n; ++k) {
                const int m = in_phase[static_cast<std::size_t>(k)];
                t(k, k) += cd(all.omega[m] * all.omega[m], 2.0 * w * all.damping_rate[m]);
            }
            Eigen::VectorXcd force = Eigen::VectorXcd::Zero(n);
            force[j] = 1.0;
            return std::abs(t.partialPivLu().solve(force)[j]);
        };
        // The peak by golden section, then each half-power point by bisection.
        double a = 0.97 * poles->omega[mode], b = 1.03 * poles->omega[mode];
        const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
        while (b - a > 1e-5 * poles->omega[mode]) {
            const double x1 = b - golden * (b - a), x2 = a + golden * (b - a);
            (response(x1) > response(x2) ? b : a) = response(x1) > response(x2) ? x2 : x1;
        }
        const double peak_w = 0.5 * (a + b), half = response(peak_w) / std::sqrt(2.0);
        const auto crossing = [&](double inside, double outside) {
            while (std::abs(outside - inside) > 1e-5 * peak_w) {
                const double mid = 0.5 * (inside + outside);
                (response(mid) > half ? inside : outside) = mid;
            }
            return 0.5 * (inside + outside);
        };
        const double width = crossing(peak_w, 1.03 * peak_w) - crossing(peak_w, 0.97 * peak_w);   // rad/s, = 2 Im w_pole
        MESSAGE("in-phase mode " << mode << ": the response peaks at " << peak_w / (2.0 * constants::pi) << " Hz, half-power half-width "
                                 << 0.5 * width << " /s; the pole " << poles->omega[mode] / (2.0 * constants::pi) << " Hz, " << poles->rate[mode] << " /s");
        CHECK(peak_w == ameoto::test::relative(poles->omega[mode]).epsilon(2e-4));
        CHECK(0.5 * width == ameoto::test::relative(poles->rate[mode]).epsilon(0.02));
    }
    // The lowest mode's radiation beside radiation_damping's far-field integral of the incompressible source
    // (5.76 /s): the pole's is lower by the air mass's growth with frequency, which makes the mode's
    // effective mass for its decay M + omega M' / 2 (11 % at ka 0.75).
    CHECK(poles->radiation_rate[0] < plain->radiation_rate[0]);
    CHECK(poles->radiation_rate[0] > 0.8 * plain->radiation_rate[0]);

    // Without radiation the poles keep the air's extra mass alone: the same frequencies within 0.1 %, the
    // material's decay lighter.
    AirCanopyOptions silent;
    silent.radiation_damping = false;
    const auto dry = build_air_canopy_modes(canopy, 1.0 / air_test_rate, silent);
    CHECK(dry->omega[0] == ameoto::test::relative(poles->omega[0]).epsilon(1e-3));
    CHECK(dry->radiation_rate[0] == 0.0);
    CHECK(dry->rate[0] < all.damping_rate[0]);
    AirCanopyOptions bad;
    bad.compressible_in_phase_ka = -1.0;
    CHECK_THROWS_AS(build_air_canopy_modes(canopy, 1.0 / air_test_rate, bad), std::invalid_argument);
}

TEST_CASE("air canopy: the two moved in-phase modes take the block's shapes with the extra mass, scaled to their residues") {
    // air_canopy.hpp: each moved mode's shape is the block's real eigenvector with Re D at its pole's
    // frequency, K x = lambda (I + Re D(w)) x, scaled so that x' (I + Re D + w Re D' / 2) x = 1, and its force
    // on the air (M_a(0) + Re(M_a(w) - M_a(0))) phi. Checked here with D solved afresh at the pole (the
    // build interpolates it between two frequencies: within 3e-4), and every other mode as it was.
    const TwoBuilds builds = default_and_incompressible();
    const Canopy& canopy = builds.canopy;
    const auto& m = builds.moved;
    const auto& plain = builds.plain;
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    const AddedMass added = canopy_added_mass(canopy, constants::air_density);
    const AirLoadedModes all = air_loaded_modes(canopy, added);
    // The in-phase block's basis: panel 0's part of each in-phase mode (one panel's worth: square).
    const std::vector<int> in_phase = in_phase_modes(all, panels, nodes);
    REQUIRE(in_phase.size() == static_cast<std::size_t>(nodes));
    const auto n = static_cast<Eigen::Index>(nodes);
    Eigen::MatrixXd psi(nodes, n);
    for (Eigen::Index j = 0; j < n; ++j) psi.col(j) = all.shapes.col(in_phase[static_cast<std::size_t>(j)]).head(nodes);
    const Eigen::PartialPivLU<Eigen::MatrixXd> basis(psi);
    const auto shape_of = [&](const AirCanopyModes& modes, int k) {
        Eigen::VectorXd phi(modes.nodes);
        for (int i = 0; i < modes.nodes; ++i) phi[i] = modes.shape[static_cast<std::size_t>(i * modes.modes + k)];
        return phi;
    };
    const double top = m->omega[in_phase[1]];
    const InPhaseAirMass series(canopy, constants::air_density, constants::speed_of_sound_air, 1.01 * top);
    const auto extra = [&](double w) {   // Re D(w) on the block's basis
        return Eigen::MatrixXd(static_cast<double>(panels) * (psi.transpose() * series.change_at(w).real() * psi));
    };
    Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index k = 0; k < n; ++k) stiffness(k, k) = all.omega[in_phase[static_cast<std::size_t>(k)]] * all.omega[in_phase[static_cast<std::size_t>(k)]];
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd first_coordinates;
    for (int j = 0; j < 2; ++j) {
        const int mode = in_phase[static_cast<std::size_t>(j)];
        const double w = m->omega[mode];
        const Eigen::VectorXd phi = shape_of(*m, mode);
        for (int p = 1; p < panels; ++p) CHECK((phi.segment(p * nodes, nodes) - phi.head(nodes)).norm() <= 1e-12 * phi.head(nodes).norm());
        const Eigen::VectorXd x = basis.solve(phi.head(nodes));
        const Eigen::MatrixXd d = extra(w);
        const double h = 1e-4 * w;
        const Eigen::MatrixXd slope = (extra(w + h) - extra(w - h)) / (2.0 * h);
        const double lambda = x.dot(stiffness * x) / x.dot((identity + d) * x);
        const double residual = (stiffness * x - lambda * (identity + d) * x).norm() / (stiffness * x).norm();
        const double residue = x.dot((identity + d + 0.5 * w * slope) * x);
        MESSAGE("in-phase mode " << mode << ": the eigen-equation's residual " << residual << ", x' (I + D + w D' / 2) x = " << residue
                                 << ", its own coordinate " << x[j] << ", the other's " << x[1 - j] << "; lambda "
                                 << std::sqrt(lambda) / (2.0 * constants::pi) << " Hz, the pole " << w / (2.0 * constants::pi) << " Hz");
        CHECK(residual < 1e-3);
        // Within 3e-3: the build's D' is the secant's over 0.95-1 times the incompressible frequency, the
        // local derivative's at its middle, 1.5 % above the lowest pole's (1.3e-3 of the residue).
        CHECK(residue == ameoto::test::relative(1.0).epsilon(3e-3));
        CHECK(x[j] > 0.0);   // the incompressible shape's sign
        // The second mode takes about a ninth of the first's shape; the first keeps its own.
        if (j == 1) CHECK(x[0] / x[1] == ameoto::test::relative(0.115).epsilon(0.05));
        else CHECK(std::abs(x[1] / x[0]) < 0.02);
        // Its force on the air: M_a(0) phi with the extra mass's, every panel alike.
        Eigen::VectorXd force = added.matrix * phi;
        const Eigen::VectorXd pushed = series.change_at(w).real() * phi.head(nodes);
        for (int p = 0; p < panels; ++p) force.segment(p * nodes, nodes) += pushed;
        CHECK((m->air_force.col(mode) - force).norm() <= 1e-3 * force.norm());
        if (j == 0) first_coordinates = x;
    }
    // Every other mode: its incompressible shape and force, bit for bit.
    for (int k = 0; k < m->modes; ++k) {
        if (k == in_phase[0] || k == in_phase[1]) continue;
        CHECK(shape_of(*m, k) == shape_of(*plain, k));
        CHECK(m->air_force.col(k) == plain->air_force.col(k));
    }
}

TEST_CASE("air canopy: impulses at three points of a panel, band levels at three listeners against the reference") {
    // Issue 19's target: third-octave band levels within 3 dB of the reference from 63 Hz to 4 kHz. The
    // cheap grid (dx = 25 mm, 0.1 s) resolves 80 Hz to 630 Hz (the 63 Hz band needs a record longer
    // than 0.1 s; above about 700 Hz the membrane's waves, under four lattice spacings, are under four
    // cells of this grid, whose near field then carries less of the air's mass). Met by the median
    // band, not yet band by band: with the converged added mass (air_loading.hpp, per-panel sub-cells)
    // the medians are 1.3-2.95 dB (2026-12-02; 1.5-4.9 with the 4 mm squares), held within 3.5 dB; the
    // worst band 2.7-11.6 dB, a single peak across a band edge (this coarse reference's own modes sit
    // 0-6 % above its converged ones, canopy_modes_test.cpp), held within 12 dB as a regression bound.
    // Full range on the converged grid: `ameoto reference canopy-bands`.
    const Canopy vacuum(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / air_test_rate);
    // Three points of panel 0: its centroid, towards the hem, towards the shaft.
    const Point2 c = vacuum.panel_centroid(0);
    const Point2 points[3] = {c, {c.x * 1.35, c.y + 0.03}, {c.x * 0.55, c.y - 0.02}};
    // Under the sanitizers the centroid only: the other two run the same code for another node, and
    // each costs about 2.5 minutes there (18 s in the Release build).
    const int point_count = ameoto::test::sanitized_build() ? 1 : 3;
    for (int k = 0; k < point_count; ++k) {
        const Point2 at = points[k];
        const CanopyHit hit = vacuum.locate(at.x, at.y);
        REQUIRE(hit.panel == 0);
        reference::CanopyBandsSetup s;
        s.reference = cheap_reference();
        s.reference.node = hit.node;
        const reference::CanopyBandsResult r = reference::compare_canopy_bands(s);
        REQUIRE(r.inside_box == std::vector<bool>{true, false, false});
        for (int l = 0; l < 3; ++l) {
            // The server's model: the modes and the compressible push (below the push's crossover, as here,
            // the modes alone within 0.2 dB: air_push_test.cpp).
            const BandComparison b = compare_levels(r.fast_push[static_cast<std::size_t>(l)], r.reference[static_cast<std::size_t>(l)]);
            MESSAGE("node " << hit.node << " listener " << l << ": median " << b.median_db << " dB, worst " << b.worst_db << " dB; " << b.table);
            CHECK(b.median_db < 3.5);
            CHECK(b.worst_db < 12.0);
        }
    }
}

TEST_CASE("air canopy: a 2 mm drop on the whole canopy, band levels at the listener against the reference") {
    // The drop scene in air (DropOnCanopy, wet impact) against the reference driven by the same contact
    // force on the struck node (all of it on one node, where the drop's masses spread over a few; the
    // fast model's own contacts). The full range on converged grids: `ameoto reference canopy-drop`
    // (docs/canopy-air.md; 63 Hz-4 kHz within 3 dB against dx 7.5 mm). Regression bound, as above: median within 6 dB, worst within 11 dB
    // (measured 2026-12-02: median 5.2 dB, worst 9.8 dB; the target is 3 dB in every band).
    DropOnCanopyConfig config;
    config.air = true;
    config.capacity = 1;
    config.max_diameter = 2e-3 * (1.0 + 1e-9);
    config.gap_m = 0.0;
    DropOnCanopy scene(config);
    const Point2 at = scene.canopy().panel_centroid(2);
    REQUIRE(scene.drop(2e-3, 0.0, at.x, at.y));
    reference::CanopyInAirSetup s = cheap_reference();
    const auto steps = static_cast<long>(s.duration_s * air_test_rate);
    std::vector<double> fast(static_cast<std::size_t>(steps)), force(static_cast<std::size_t>(steps));
    float frame[1];
    for (long n = 0; n < steps; ++n) {
        scene.process_frame(frame);
        fast[static_cast<std::size_t>(n)] = frame[0] * config.full_scale_pa;
        force[static_cast<std::size_t>(n)] = -scene.contact_force().z;   // on the membrane, along +z
    }
    // Under the sanitizers the drop in air runs (above) and the reference's comparison, which the
    // impulse case above already drives, is left to the Release run (about 25 s there).
    if (ameoto::test::stop_here_if_sanitized("the FDTD comparison runs under them in the impulse case")) return;
    const CanopyHit hit = scene.canopy().locate(at.x, at.y);
    reference::CanopyBandsSetup bands;
    bands.reference = s;
    bands.reference.panel = hit.panel;
    bands.reference.node = hit.node;
    bands.reference.force_samples = force;
    bands.reference.force_interval_s = 1.0 / air_test_rate;
    bands.listeners = {{0.0, 0.0, -config.listener_below_m}};
    const reference::CanopyBandsResult r = reference::compare_canopy_bands(bands);
    const BandComparison b = compare_levels(reference::third_octave_levels(fast, 1.0 / air_test_rate, bands.low_hz, bands.high_hz),
                                            r.reference[0]);
    MESSAGE("2 mm drop: median " << b.median_db << " dB, worst " << b.worst_db << " dB; " << b.table);
    // Measured 2026-12-02: median 1.34 dB, worst 7.06 (the 157 Hz band); bounds as above.
    CHECK(b.median_db < 3.5);
    CHECK(b.worst_db < 12.0);
}

TEST_CASE("air canopy: air off is the lattice in vacuum, bit for bit; on is another sound, audio-safe") {
    // DropOnCanopyConfig::air false must leave the seed's path untouched: the same samples as a
    // configuration that never names air, and different ones with it on. The air-loaded scene's
    // drop() and process_frame() run under the real-time probe (no allocation, lock or block).
    DropOnCanopyConfig plain;
    plain.capacity = 1;
    plain.max_diameter = 2e-3 * (1.0 + 1e-9);
    DropOnCanopyConfig off = plain, on = plain;
    off.air = false;
    on.air = true;
    on.capacity = 2;   // room for a second drop under the probe
    DropOnCanopy a(plain), b(off), c(on);
    for (DropOnCanopy* d : {&a, &b, &c}) REQUIRE(d->drop(2e-3, 0.0, 0.25, 0.05));
    CHECK_FALSE(a.canopy().in_air());
    CHECK(c.canopy().in_air());
    float fa[1], fb[1], fc[1];
    bool same = true, differs = false;
    std::vector<float> vacuum(4800);
    for (int n = 0; n < 4800; ++n) {
        a.process_frame(fa);
        b.process_frame(fb);
        same = same && fa[0] == fb[0];
        vacuum[static_cast<std::size_t>(n)] = fa[0];
    }
    bool second = false;
    test::RtAudit audit;
    {
        test::RtAudit::Scope scope;
        for (int n = 0; n < 4800; ++n) {
            if (n == 2400) second = c.drop(2e-3, 0.0, -0.2, 0.1);   // a second drop, under the probe
            c.process_frame(fc);
            differs = differs || fc[0] != vacuum[static_cast<std::size_t>(n)];
        }
    }
    CHECK(audit.violations() == 0);
    CHECK(audit.entries() > 0);
    INFO(audit.first());
    CHECK(same);
    CHECK(differs);
    CHECK(second);
    CHECK(c.stats().collisions > 0);
}

TEST_CASE("air canopy: the reference's double layer at 0.3 m is its box's own pressure") {
    // The extrapolation the far listeners rely on (screen_far_field.hpp), checked where the box hears
    // directly: band levels within 1 dB from 80 Hz to 1 kHz.
    // An accuracy check only: the double layer and the node forces run under the sanitizers inside
    // compare_canopy_bands (the impulse case), so there it is left to the Release run (12 s there).
    if (ameoto::test::stop_here_if_sanitized("the double layer runs under them in the impulse case")) return;
    reference::CanopyInAirSetup s = cheap_reference();
    s.duration_s = 0.06;
    s.record_forces = true;
    s.record_nodes = false;
    s.listeners = {{0.0, 0.0, -0.3}};
    const Canopy vacuum(CanopyGeometry{}, MembraneMaterial::nylon_canopy(), 1.0 / air_test_rate);
    const reference::CanopyInAirResult r = reference::run_canopy_in_air(s);
    const reference::NodeForcesOnAir nodes = reference::node_forces_on_air(vacuum, r);
    const auto p = reference::double_layer_pressure(nodes.force, nodes.positions, nodes.normals, r.sample_interval_s, s.listeners[0],
                                                    constants::speed_of_sound_air, static_cast<int>(r.pressure[0].size()));
    const auto a = reference::third_octave_levels(p, r.sample_interval_s, 80.0, 1000.0);
    const auto b = reference::third_octave_levels(r.pressure[0], r.sample_interval_s, 80.0, 1000.0);
    double worst = 0.0;
    std::string table;
    for (std::size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::abs(a[i].level_db - b[i].level_db));
        table += std::to_string(a[i].level_db - b[i].level_db).substr(0, 5) + " ";
    }
    MESSAGE("double layer vs box at 0.3 m: worst " << worst << " dB; " << table);
    CHECK(worst < 1.0);
}

}  // namespace ameoto
