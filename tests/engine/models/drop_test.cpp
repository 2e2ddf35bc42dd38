// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/drop: mass counts, the Rayleigh calibration (eigenvalue and simulated), Lamb
// damping, the break threshold on a rigid floor, drag presets, determinism.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "engine/core/body3d_drag.hpp"
#include "engine/core/connected_components.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/drop.hpp"
#include "engine/scene/terminal_speed.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using ameoto::Body3D;
using ameoto::DragPreset;
using ameoto::Liquid;
using ameoto::Vec3;

namespace {

// The seed's water but with 0.0728 N/m, the value physics.md's Rayleigh table uses.
const Liquid kWater20{"water at 20 C", 998.0, 0.0728, 1.0e-3};

// Stretches the drop along z by (1 + e) and shrinks x, y by 1 / sqrt(1 + e) about its centre of mass
// (volume kept): the liquid's n = 2 shape.
void stretch(Body3D& body, double e) {
    const Vec3 c = body.centre_of_mass();
    const double sz = 1.0 + e, sx = 1.0 / std::sqrt(sz);
    for (int i = 0; i < body.mass_count(); ++i) {
        const Vec3 p = body.position(i) - c;
        body.set_position(i, c + Vec3{sx * p.x, sx * p.y, sz * p.z});
    }
}

// The n = 2 shape observable: the second moment along z minus the mean of those along x and y.
double elongation(const Body3D& body) {
    const Vec3 c = body.centre_of_mass();
    double q = 0.0;
    for (int i = 0; i < body.mass_count(); ++i) {
        const Vec3 p = body.position(i) - c;
        q += body.mass(i) * (p.z * p.z - 0.5 * (p.x * p.x + p.y * p.y));
    }
    return q;
}

// Frequency (Hz) of the largest peak of a Hann-windowed DFT of x (sampled every dt) between 0.3 and 3
// times f_guess: a scan in steps of 0.5 % of f_guess, refined around its peak in steps of 0.01 %.
double peak_frequency(const std::vector<double>& x, double dt, double f_guess) {
    double mean = 0.0;
    for (double v : x) mean += v;
    mean /= static_cast<double>(x.size());
    const std::size_t n = x.size();
    std::vector<double> windowed(n);
    for (std::size_t i = 0; i < n; ++i)
        windowed[i] = (x[i] - mean) * (0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(n - 1)));
    auto magnitude = [&](double f) {
        std::complex<double> acc = 0.0, phase = 1.0;
        const std::complex<double> rot = std::polar(1.0, -2.0 * kPi * f * dt);
        for (std::size_t i = 0; i < n; ++i) {
            acc += windowed[i] * phase;
            phase *= rot;
        }
        return std::abs(acc);
    };
    auto scan = [&](double from, double to, double step) {
        double best = -1.0, best_f = from;
        for (double f = from; f <= to; f += step)
            if (const double m = magnitude(f); m > best) {
                best = m;
                best_f = f;
            }
        return best_f;
    };
    const double coarse = scan(0.3 * f_guess, 3.0 * f_guess, 5e-3 * f_guess);
    return scan(coarse - 5e-3 * f_guess, coarse + 5e-3 * f_guess, 1e-4 * f_guess);
}

struct FreeOscillation {
    double frequency = 0.0;               // Hz, DFT peak
    std::vector<double> elongation;       // sampled every 8 steps
    ameoto::DropCalibration calibration;
};

// A free drop (no gravity, no drag), stretched 1 % and let go for `periods` Rayleigh periods at 48 kHz.
FreeOscillation oscillate(double diameter, const Liquid& liquid, double periods) {
    auto drop = ameoto::make_drop(diameter, liquid, Vec3{}, Vec3{}, DragPreset::none);
    Body3D& body = drop.body;
    body.set_gravity(Vec3{});
    stretch(body, 0.01);
    body.finalize(kT);
    FreeOscillation out;
    out.calibration = drop.calibration;
    const int steps = static_cast<int>(periods / (drop.calibration.rayleigh_hz * kT));
    for (int n = 0; n < steps; ++n) {
        if (n % 8 == 0) out.elongation.push_back(elongation(body));
        body.step();
    }
    out.frequency = peak_frequency(out.elongation, 8.0 * kT, drop.calibration.rayleigh_hz);
    return out;
}

// A rigid, frictionless, inelastic floor at z = 0 (test only): each mass below it is pushed up by a
// critically damped penalty spring of 20 000 rad/s (a mass at 9 m/s sinks about 0.2 mm), never pulled.
// Returns the total force applied for the next step.
Vec3 push_off_floor(Body3D& body) {
    Vec3 total{};
    for (int i = 0; i < body.mass_count(); ++i) {
        const Vec3 p = body.position(i);
        if (p.z >= 0.0) continue;
        const double m = body.mass(i), omega = 2e4;
        const double f = std::max(0.0, m * omega * omega * (-p.z) - 2.0 * m * omega * body.velocity(i).z);
        body.apply_force(i, Vec3{0.0, 0.0, f});
        total = total + Vec3{0.0, 0.0, f};
    }
    return total;
}

struct Impact {
    int pieces = 0, largest = 0, masses = 0, broken = 0;
    double mass_before = 0.0, mass_after = 0.0, mass_in_pieces = 0.0;
    Vec3 momentum_error{};   // P(end) - P(0) - (floor and gravity impulses)
    double momentum_scale = 0.0;
};

// A drop of diameter D touching the floor at speed v, run for 20 ms with the given drag.
Impact strike(double diameter, double speed, DragPreset drag, const ameoto::DropOptions& options = {}) {
    auto drop = ameoto::make_drop(diameter, ameoto::liquids::water(), Vec3{0.0, 0.0, 0.5 * diameter}, Vec3{0.0, 0.0, -speed},
                                  drag, options);
    Body3D& body = drop.body;
    body.finalize(kT);
    Impact out;
    out.masses = body.mass_count();
    out.mass_before = body.total_mass();
    const Vec3 p0 = body.momentum();
    Vec3 impulse{};
    const Vec3 weight = body.total_mass() * Vec3{0.0, 0.0, -ameoto::constants::gravity};
    for (int n = 0; n < static_cast<int>(0.02 / kT); ++n) {
        impulse = impulse + kT * (push_off_floor(body) + weight);
        body.step();
    }
    ameoto::ConnectedComponents cc;
    cc.init(body.mass_count());
    out.pieces = cc.compute(body);
    for (int c = 0; c < out.pieces; ++c) out.largest = std::max(out.largest, cc.size_of(c));
    for (int i = 0; i < body.mass_count(); ++i) out.mass_in_pieces += body.mass(i);
    out.mass_after = body.total_mass();
    out.broken = body.broken_link_count();
    out.momentum_error = body.momentum() - p0 - impulse;
    out.momentum_scale = body.total_mass() * speed;
    return out;
}

double mundo_k(double d, double v, const Liquid& l) {
    const double we = l.density * v * v * d / l.surface_tension, re = l.density * v * d / l.viscosity;
    return std::sqrt(we) * std::pow(re, 0.25);
}

}  // namespace

TEST_CASE("drop: one mass per 1 mm drop volume, the drop's mass exact") {
    for (double d_mm : {0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0}) {
        CAPTURE(d_mm);
        const double d = d_mm * 1e-3;
        const auto c = ameoto::calibrate_drop(d, ameoto::liquids::water());
        const double target = std::max(1.0, std::round(d_mm * d_mm * d_mm));
        if (d_mm <= 1.0) {
            CHECK(c.masses == 1);   // cannot oscillate or break
            CHECK(c.stiffness == 0.0);
        } else {
            CHECK(std::abs(c.masses - target) <= 0.2 * target);   // whole shells (lattice_ball.hpp)
        }
        const double m = 998.0 * kPi * d * d * d / 6.0;
        CHECK(c.total_mass == ameoto::test::relative(m).epsilon(1e-15));
        CHECK(c.node_mass * c.masses == ameoto::test::relative(m).epsilon(1e-14));
    }
    CHECK(ameoto::calibrate_drop(5e-3, ameoto::liquids::water()).masses == 122);   // 125 targeted
}

TEST_CASE("drop: Rayleigh's n = 2 frequency and Lamb's decay time (physics.md section 4)") {
    // physics.md: sigma 0.0728, rho 998: 344, 122, 66, 31 Hz at 1, 2, 3, 5 mm (rounded to 1 Hz).
    CHECK(ameoto::rayleigh_frequency(1e-3, kWater20) == doctest::Approx(344.0).epsilon(0.5 / 344.0 + 1e-3));
    CHECK(ameoto::rayleigh_frequency(2e-3, kWater20) == doctest::Approx(122.0).epsilon(0.5 / 122.0 + 1e-3));
    CHECK(ameoto::rayleigh_frequency(3e-3, kWater20) == doctest::Approx(66.0).epsilon(0.5 / 66.0 + 1e-3));
    CHECK(ameoto::rayleigh_frequency(5e-3, kWater20) == doctest::Approx(31.0).epsilon(0.5 / 31.0 + 1e-3));
    // tau = a^2 / ((n-1)(2n+1) nu): n = 2, a = 1 mm, nu = 1e-6: 0.2 s.
    const Liquid nu1{"nu = 1e-6", 1000.0, 0.07, 1e-3};
    CHECK(ameoto::lamb_decay_time(2e-3, nu1) == ameoto::test::relative(0.2).epsilon(1e-12));
    CHECK(ameoto::lamb_decay_time(2e-3, nu1, 3) == ameoto::test::relative(1e-6 / (2.0 * 7.0 * 1e-6)).epsilon(1e-12));
}

TEST_CASE("drop: the calibration's closed forms (k, z, break force, core)") {
    const Liquid& water = ameoto::liquids::water();
    const auto c = ameoto::calibrate_drop(5e-3, water);
    const double omega2 = 2.0 * kPi * c.rayleigh_hz;
    CHECK(c.stiffness == ameoto::test::relative(c.node_mass * omega2 * omega2 / c.lambda2).epsilon(1e-14));
    // z = 2 k / (tau omega^2) = (5/4) (mu a / sigma) k
    CHECK(c.damping == ameoto::test::relative(1.25 * water.viscosity * 2.5e-3 / water.surface_tension * c.stiffness).epsilon(1e-12));
    CHECK(c.break_force == ameoto::test::relative(0.5 * kPi * water.surface_tension * c.spacing).epsilon(1e-14));
    CHECK(c.core_length == ameoto::test::relative(0.9 * c.spacing).epsilon(1e-14));
    CHECK(c.core_stiffness == ameoto::test::relative(c.node_mass * std::pow(15.0 / c.spacing, 2)).epsilon(1e-14));
    // k = 32 pi sigma / (3 N lambda): independent of the diameter for a given lattice.
    CHECK(c.stiffness == ameoto::test::relative(32.0 * kPi * water.surface_tension / (3.0 * c.masses * c.lambda2)).epsilon(1e-12));
    // Breaking strain F / (k h) = 3 N lambda / 64, independent of sigma: 1.18 at 5 mm, 0.33 at 2 mm.
    CHECK(c.break_force / (c.stiffness * c.spacing) == ameoto::test::relative(3.0 * 122 * c.lambda2 / 64.0).epsilon(1e-12));
    const auto c2 = ameoto::calibrate_drop(2e-3, water);
    CHECK(c2.break_force / (c2.stiffness * c2.spacing) == ameoto::test::relative(3.0 * 7 * 1.0 / 64.0).epsilon(1e-9));
    ameoto::DropOptions no_core;
    no_core.core = false;
    CHECK(ameoto::calibrate_drop(5e-3, water, no_core).core_stiffness == 0.0);
    // Arrival speed: Gunn & Kinzer for water, times sqrt(rho / rho_w) otherwise.
    CHECK(c.arrival_speed == ameoto::terminal_speed(5e-3));
    CHECK(ameoto::calibrate_drop(5e-3, ameoto::liquids::heavy_oil()).arrival_speed ==
          ameoto::test::relative(ameoto::terminal_speed(5e-3) * std::sqrt(960.0 / 998.0)).epsilon(1e-14));
    CHECK_THROWS_AS(ameoto::calibrate_drop(0.0, water), std::invalid_argument);
    CHECK_THROWS_AS(ameoto::calibrate_drop(2e-3, Liquid{"bad", 1.0, 0.07, 1e-3}), std::invalid_argument);
}

TEST_CASE("drop: the n = 2 eigenvalue by Lanczos equals the dense eigensolver's; it is not the lowest") {
    for (int target : {2, 3, 8, 27, 125}) {
        CAPTURE(target);
        const auto lattice = ameoto::drop_lattice(target);
        const auto& s = lattice->shape;
        const int n = 3 * s.mass_count();
        Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
        for (int l = 0; l < s.link_count(); ++l) {
            const int a = s.link_a[static_cast<std::size_t>(l)], b = s.link_b[static_cast<std::size_t>(l)];
            const Vec3 d = s.position[static_cast<std::size_t>(a)] - s.position[static_cast<std::size_t>(b)];
            const Vec3 u = d / ameoto::norm(d);
            const double uu[3] = {u.x, u.y, u.z};
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    k(3 * a + i, 3 * a + j) += uu[i] * uu[j];
                    k(3 * b + i, 3 * b + j) += uu[i] * uu[j];
                    k(3 * a + i, 3 * b + j) -= uu[i] * uu[j];
                    k(3 * b + i, 3 * a + j) -= uu[i] * uu[j];
                }
        }
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(k);
        Eigen::VectorXd u0(n);
        for (int i = 0; i < s.mass_count(); ++i) {
            const Vec3 p = s.position[static_cast<std::size_t>(i)];
            u0.segment<3>(3 * i) << -0.5 * p.x, -0.5 * p.y, p.z;
        }
        // Dense: the eigenvalue (degenerate ones grouped) with the largest share of the stretch.
        double total = 0.0, best = 0.0, best_lambda = 0.0, lowest = 0.0;
        for (int i = 0; i < n; ++i)
            if (es.eigenvalues()(i) > 1e-9) total += std::pow(es.eigenvectors().col(i).dot(u0), 2);
        for (int i = 0; i < n;) {
            const double lambda = es.eigenvalues()(i);
            double w = 0.0;
            int j = i;
            for (; j < n && std::abs(es.eigenvalues()(j) - lambda) < 1e-9 * (1.0 + lambda); ++j)
                w += std::pow(es.eigenvectors().col(j).dot(u0), 2);
            if (lambda > 1e-9) {
                if (lowest == 0.0) lowest = lambda;
                if (w / total > best) {
                    best = w / total;
                    best_lambda = lambda;
                }
            }
            i = j;
        }
        MESSAGE(s.mass_count() << " masses: lambda_2 " << lattice->lambda2 << " (share " << lattice->weight2
                               << "), lowest non-zero " << lowest);
        CHECK(lattice->lambda2 == ameoto::test::relative(best_lambda).epsilon(1e-9));   // both exact to rounding
        CHECK(std::abs(lattice->weight2 - best) < 0.01);   // near-degenerate neighbours are grouped differently
        CHECK(lattice->weight2 > 0.5);   // the stretch is mostly one mode
        if (target == 27) CHECK(lowest < 0.25 * lattice->lambda2);   // a solid's soft mode, not the liquid's
    }
}

TEST_CASE("drop: a free drop stretched 1 % oscillates within 10 % of Rayleigh (simulated at 48 kHz)") {
    struct Case {
        double d_mm;
        Liquid liquid;
    };
    const Liquid& oil = ameoto::liquids::heavy_oil();
    // Heavy oil is overdamped at its viscosity (below): its frequency is checked with the same
    // density and surface tension, hence the same stiffness, and negligible viscosity.
    const Liquid inviscid_oil{"heavy_oil, inviscid", oil.density, oil.surface_tension, 1e-6};
    const Case cases[] = {{2.0, ameoto::liquids::water()}, {3.0, ameoto::liquids::water()},
                          {5.0, ameoto::liquids::water()}, {5.0, ameoto::liquids::milk()},
                          {5.0, inviscid_oil}};
    for (const auto& c : cases) {
        CAPTURE(c.d_mm);
        CAPTURE(c.liquid.name);
        const auto r = oscillate(c.d_mm * 1e-3, c.liquid, 20.0);
        const double f2 = r.calibration.rayleigh_hz;
        MESSAGE(c.d_mm << " mm " << c.liquid.name << ": " << r.calibration.masses << " masses, Rayleigh " << f2
                       << " Hz, simulated " << r.frequency << " Hz (" << 100.0 * (r.frequency / f2 - 1.0) << " %)");
        CHECK(r.frequency == doctest::Approx(f2).epsilon(0.10));   // issue 4, physics.md check 2: 10 %
        // In fact to the DFT's 0.01 % grid: the lattice's mode is placed exactly, and the explicit
        // scheme's warping at omega T = 0.003-0.016 is below 1e-5.
        CHECK(r.frequency == doctest::Approx(f2).epsilon(3e-4));
    }
}

TEST_CASE("drop: the n = 2 mode decays at Lamb's rate; heavy oil is overdamped") {
    // 2 mm water: tau = 0.131 s. The n = 2 mode's amplitude in the first and the last 10 periods of
    // 0.25 s, each by a Hann-windowed DFT at its frequency (which rejects the lattice's other mode in
    // the stretch, at 0.72 f_2, that decays at half the rate): ratio exp(-dt / tau).
    const double d = 2e-3;
    const auto r = oscillate(d, ameoto::liquids::water(), 0.25 * ameoto::rayleigh_frequency(d, ameoto::liquids::water()));
    const double dt = 8.0 * kT, f2 = r.calibration.rayleigh_hz;
    const auto window = static_cast<std::size_t>(10.0 / (f2 * dt));
    auto amplitude = [&](std::size_t from) {
        std::complex<double> acc = 0.0;
        for (std::size_t i = 0; i < window; ++i) {
            const double w = 0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(window - 1));
            acc += r.elongation[from + i] * w * std::polar(1.0, -2.0 * kPi * f2 * static_cast<double>(i) * dt);
        }
        return std::abs(acc);
    };
    const std::size_t last = r.elongation.size() - window;
    const double rate = std::log(amplitude(0) / amplitude(last)) / (static_cast<double>(last) * dt);
    const double lamb = 1.0 / r.calibration.decay_time;
    MESSAGE("2 mm water: decay rate " << rate << " 1/s, Lamb 1/tau = " << lamb);
    CHECK(std::abs(rate / lamb - 1.0) < 0.02);   // C = beta K: exact for the mode; 2 % for window leakage

    // Heavy oil, 5 mm: 1/tau = 304 1/s > omega_2 = 131 rad/s: the stretch relaxes without crossing zero.
    const auto oil = oscillate(5e-3, ameoto::liquids::heavy_oil(), 5.0);
    CHECK(1.0 / oil.calibration.decay_time > 2.0 * kPi * oil.calibration.rayleigh_hz);
    const double start = oil.elongation.front();
    REQUIRE(start > 0.0);
    double least = start;
    for (double q : oil.elongation) least = std::min(least, q);
    MESSAGE("5 mm heavy oil: elongation " << start << " -> " << oil.elongation.back() << ", least " << least);
    CHECK(least > 0.0);                              // no overshoot: no oscillation
    CHECK(oil.elongation.back() < 0.05 * start);     // but it does relax within 5 Rayleigh periods (0.24 s)
}

TEST_CASE("drop: a 5 mm drop at terminal speed breaks up on a rigid floor; masses and momentum conserved") {
    const double d = 5e-3, v = ameoto::terminal_speed(d);
    const Impact r = strike(d, v, DragPreset::none);   // no drag: the momentum balance is exact
    MESSAGE("5 mm at " << v << " m/s (K = " << mundo_k(d, v, ameoto::liquids::water()) << "): " << r.pieces
                       << " pieces, largest " << r.largest << " of " << r.masses << " masses, " << r.broken << " links broken");
    CHECK(r.pieces > 1);
    CHECK(r.masses == 122);
    CHECK(r.mass_after == r.mass_before);        // exact: masses are never created or removed
    CHECK(r.mass_in_pieces == r.mass_before);
    // Momentum: P(20 ms) - P(0) = floor impulses + weight * t. Internal links cancel to rounding
    // (symplectic Euler, body3d.hpp): 1e-12 of m v.
    CHECK(ameoto::norm(r.momentum_error) < 1e-12 * r.momentum_scale);

    // Without the incompressible cores the springs, 1e3 times too soft to stop an impact, let the
    // lattice fold into a heap: it stays whole (drop.hpp, "Incompressibility").
    ameoto::DropOptions no_core;
    no_core.core = false;
    CHECK(strike(d, v, DragPreset::none, no_core).pieces == 1);

    // With Beard's drag (the default) it breaks up as well.
    const Impact dragged = strike(d, v, DragPreset::quadratic);
    CHECK(dragged.pieces > 1);
    CHECK(dragged.mass_after == dragged.mass_before);
}

TEST_CASE("drop: 0.5 and 1 mm drops (one mass) cannot break; 2 and 3 mm drops break at terminal speed") {
    for (double d_mm : {0.5, 1.0}) {
        CAPTURE(d_mm);
        const Impact r = strike(d_mm * 1e-3, ameoto::terminal_speed(d_mm * 1e-3), DragPreset::quadratic);
        CHECK(r.masses == 1);
        CHECK(r.pieces == 1);
    }
    for (double d_mm : {2.0, 3.0}) {
        CAPTURE(d_mm);
        const Impact r = strike(d_mm * 1e-3, ameoto::terminal_speed(d_mm * 1e-3), DragPreset::quadratic);
        MESSAGE(d_mm << " mm: " << r.pieces << " pieces of " << r.masses << " masses, largest " << r.largest);
        CHECK(r.pieces > 1);
        CHECK(r.mass_after == r.mass_before);
    }
}

TEST_CASE("drop: the model's splash threshold: a 5 mm drop set down at 0.5 m/s stays whole") {
    // Mundo's K = We^(1/2) Re^(1/4) at 0.5 m/s is 28, below 57.7: no splash. The model's onset for
    // 5 mm is about 1.07 m/s (K = 67), documented in docs/drop.md.
    const double d = 5e-3;
    CHECK(mundo_k(d, 0.5, ameoto::liquids::water()) < 57.7);
    const Impact slow = strike(d, 0.5, DragPreset::quadratic);
    CHECK(slow.pieces == 1);
    CHECK(slow.broken == 0);
}

TEST_CASE("drop: drag presets: Beard's quadratic reaches the terminal speed, the seed's linear does not") {
    // A 2 mm drop let go at rest: after 3 s with quadratic drag its speed is within 3 % of Gunn &
    // Kinzer (physics.md check 1; Beard's fit is within 2.2 %); with the seed's linear drag it is far
    // faster (its own terminal speed is m g / c per mass, hundreds of m/s).
    const double d = 2e-3;
    auto speed_after = [&](DragPreset preset, double seconds) {
        auto drop = ameoto::make_drop(d, ameoto::liquids::water(), Vec3{}, Vec3{}, preset);
        drop.body.finalize(kT);
        for (int n = 0; n < static_cast<int>(seconds / kT); ++n) drop.body.step();
        return -drop.body.momentum().z / drop.body.total_mass();
    };
    const double quadratic = speed_after(DragPreset::quadratic, 3.0);
    CHECK(quadratic == ameoto::test::relative(ameoto::terminal_speed(d)).epsilon(0.03));
    CHECK(speed_after(DragPreset::seed_linear, 3.0) > 25.0);
    CHECK(speed_after(DragPreset::none, 1.0) == doctest::Approx(ameoto::constants::gravity).epsilon(1e-9));

    auto drop = ameoto::make_drop(d, ameoto::liquids::water(), Vec3{}, std::nullopt, DragPreset::seed_linear);
    CHECK(drop.body.velocity(0).z == -ameoto::terminal_speed(d));   // default: arrives at terminal speed
}

TEST_CASE("drop: after a breakup each piece has the drag of a drop of its own volume") {
    const double d = 3e-3;
    auto drop = ameoto::make_drop(d, ameoto::liquids::water(), Vec3{0.0, 0.0, 0.5 * d}, std::nullopt, DragPreset::quadratic);
    Body3D& body = drop.body;
    const int n = body.mass_count();
    const double b = ameoto::drag::drop_quadratic_drag(d);
    for (int i = 0; i < n; ++i) CHECK(body.quadratic_drag(i) == ameoto::test::relative(b / n).epsilon(1e-15));   // intact: b / N each
    body.finalize(kT);
    for (int step = 0; step < static_cast<int>(0.01 / kT); ++step) {
        push_off_floor(body);
        body.step();
    }
    ameoto::ConnectedComponents cc;
    cc.init(n);
    REQUIRE(cc.compute(body) > 1);
    ameoto::set_piece_drag(body, drop.info, drop.calibration, cc, DragPreset::quadratic);
    std::vector<double> piece_drag(static_cast<std::size_t>(cc.count()), 0.0);
    for (int i = 0; i < n; ++i) piece_drag[static_cast<std::size_t>(cc.component_of(i))] += body.quadratic_drag(i);
    for (int c = 0; c < cc.count(); ++c) {
        const double d_piece = d * std::cbrt(static_cast<double>(cc.size_of(c)) / n);   // same volume
        CHECK(piece_drag[static_cast<std::size_t>(c)] == ameoto::test::relative(ameoto::drag::drop_quadratic_drag(d_piece)).epsilon(1e-12));
    }
    // A piece of one mass has more drag per mass than the intact drop had (area over volume).
    CHECK(ameoto::drag::drop_quadratic_drag(d / std::cbrt(static_cast<double>(n))) > b / n);
}

TEST_CASE("drop: the same inputs give bit-identical trajectories through a breakup") {
    auto run = [] {
        auto drop = ameoto::make_drop(4e-3, ameoto::liquids::water(), Vec3{0.01, -0.02, 2e-3}, std::nullopt);
        drop.body.finalize(kT);
        for (int step = 0; step < 600; ++step) {
            push_off_floor(drop.body);
            drop.body.step();
        }
        std::vector<double> state;
        for (int i = 0; i < drop.body.mass_count(); ++i) {
            const Vec3 p = drop.body.position(i), v = drop.body.velocity(i);
            state.insert(state.end(), {p.x, p.y, p.z, v.x, v.y, v.z});
        }
        state.push_back(drop.body.broken_link_count());
        return state;
    };
    const auto first = run(), second = run();
    CHECK(first.back() > 0.0);   // it did break
    CHECK(first == second);
}
