// SPDX-License-Identifier: GPL-3.0-or-later
// The integrators' measured accuracy (physics.md s.3, s.5 check 4): frequency warping, undamped energy
// drift over 10^6 steps, and the modal scheme against the explicit one. Each case checks its tolerance;
// AMEOTO_PRINT_TABLES=1 ./build/tests/engine_tests -tc='table: *' prints the markdown tables kept in
// docs/integrators.md ("Measured accuracy").
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "tests/engine/core/integrators/test_bodies.hpp"
#include "tests/support/test_constants.hpp"
#include "tests/support/relative_approx.hpp"

using namespace ameoto::test::common;

using namespace ameoto;
using namespace ameoto::test;

  // namespace

TEST_CASE("table: frequency warping of a single oscillator, per integrator") {
    struct Case {
        Integrator integrator;
        double w0t;
        std::function<double(double)> formula;   // omega T as a function of omega0 T
        const char* formula_text;
        int steps;
    };
    const auto asin_w = [](double x) { return 2.0 * std::asin(x / 2.0); };
    const auto atan_w = [](double x) { return 2.0 * std::atan(x / 2.0); };
    const auto be_w = [](double x) { return std::atan(x); };
    const auto exact = [](double x) { return x; };
    std::vector<Case> cases;
    for (double x : {0.5, 1.0, 1.9}) cases.push_back({Integrator::explicit_verlet, x, asin_w, "2 asin(w0T/2)", 100000});
    for (double x : {0.5, 1.0, 1.9}) cases.push_back({Integrator::symplectic_euler, x, asin_w, "2 asin(w0T/2)", 100000});
    for (double x : {0.5, 2.0, 5.0, 10.0}) cases.push_back({Integrator::trapezoidal, x, atan_w, "2 atan(w0T/2)", 100000});
    for (double x : {0.1, 0.5, 2.0}) cases.push_back({Integrator::backward_euler, x, be_w, "atan(w0T)", 3000});
    for (double x : {0.5, 2.0, 3.0}) cases.push_back({Integrator::modal, x, exact, "w0T (exact)", 100000});
    std::string table =
        "\n| integrator | omega0 T | formula (omega T) | formula | measured | error vs formula | omega / omega0 |\n"
        "|---|---|---|---|---|---|---|\n";
    for (const auto& c : cases) {
        CAPTURE(std::string(integrator_name(c.integrator)));
        CAPTURE(c.w0t);
        auto net = one_oscillator(1e-3, c.w0t / kT);
        net.finalize(kT, options_for(c.integrator, StabilityPolicy::none));   // no sub-steps: the scheme itself
        REQUIRE(net.stability().sub_steps == 1);
        net.apply_force(0, 1.0);
        std::vector<double> x;
        for (int n = 0; n < c.steps; ++n) {
            net.step();
            x.push_back(net.position(0));
        }
        const double measured = zero_crossing_omega(x, kT) * kT, expected = c.formula(c.w0t);
        // physics.md s.5 check 4 (brief: 0.1 %).
        CHECK(measured == ameoto::test::relative(expected).epsilon(1e-3));
        char line[256];
        std::snprintf(line, sizeof line, "| %s | %.1f | %s | %.6f | %.6f | %+.1e | %.4f |\n", integrator_name(c.integrator),
                      c.w0t, c.formula_text, expected, measured, measured / expected - 1.0, measured / c.w0t);
        table += line;
    }
    if (print_tables()) std::printf("%s", table.c_str());
}

TEST_CASE("table: undamped energy over 10^6 steps, per integrator") {
    struct Body {
        std::string name;
        std::function<TransverseNetwork()> make;
        int force_at;
    };
    const std::vector<Body> bodies = {
        {"1 mass", [] { return one_oscillator(1e-3, 1.0); }, 0},
        {"20-mass membrane", [] { return lattice_membrane(20).network; }, 5},
    };
    struct Run {
        Integrator integrator;
        double omega_t;   // omega_max T the step is chosen for
    };
    const std::vector<Run> runs = {{Integrator::explicit_verlet, 0.01}, {Integrator::symplectic_euler, 0.01},
                                   {Integrator::trapezoidal, 0.01},     {Integrator::backward_euler, 0.01},
                                   {Integrator::explicit_verlet, 1.0},  {Integrator::trapezoidal, 10.0}};
    std::string table =
        "\n| body | integrator | omega_max T | max abs(E - E0) / E0 | same, last 10 % | E_end / E0 | monotone |\n"
        "|---|---|---|---|---|---|---|\n";
    for (const auto& b : bodies) {
        for (const auto& r : runs) {
            CAPTURE(b.name);
            CAPTURE(std::string(integrator_name(r.integrator)));
            CAPTURE(r.omega_t);
            auto net = b.make();
            const double omega_max = power_iteration_omega_max(net.arrays());
            const double t = r.omega_t / omega_max;
            net.finalize(t, options_for(r.integrator, StabilityPolicy::none));
            REQUIRE(net.stability().sub_steps == 1);
            net.apply_force(b.force_at, 1.0);
            net.step();
            const double e0 = net.kinetic_plus_potential_energy();
            double worst = 0.0, worst_late = 0.0, previous = e0;
            bool monotone = true;
            const int steps = 1000000;
            for (int n = 0; n < steps; ++n) {
                net.step();
                const double e = net.kinetic_plus_potential_energy();
                const double dev = std::abs(e - e0) / e0;
                worst = std::max(worst, dev);
                if (n >= steps - steps / 10) worst_late = std::max(worst_late, dev);
                monotone = monotone && e <= previous;
                previous = e;
            }
            const double end = net.kinetic_plus_potential_energy() / e0;
            if (r.integrator == Integrator::trapezoidal) {
                // trapezoidal.hpp: conserved to rounding at any omega T (1e-9 over 10^6 steps).
                CHECK(worst < 1e-9);
            } else if (r.integrator == Integrator::backward_euler) {
                CHECK(monotone);   // backward_euler.hpp: E[n+1] <= E[n] at every step
                CHECK(end < 1.0);
            } else if (r.omega_t <= 0.01) {
                // Brief: bounded within 1 %; the schemes keep a shadow energy, the measured one ripples by
                // up to omega T / 2 = 0.5 % and does not drift (the last 10 % are no worse).
                CHECK(worst < 0.01);
                CHECK(worst_late <= worst);
            } else {
                // omega_max T = 1: the ripple is large (up to ~omega T / 2 of the high modes' share) but
                // bounded: the last 10 % of the run is no worse than the whole.
                CHECK(worst < 1.0);
                CHECK(worst_late <= worst);
            }
            char line[256];
            std::snprintf(line, sizeof line, "| %s | %s | %g | %.2e | %.2e | %.6f | %s |\n", b.name.c_str(),
                          integrator_name(r.integrator), r.omega_t, worst, worst_late, end, monotone ? "yes" : "no");
            table += line;
        }
    }
    if (print_tables()) std::printf("%s", table.c_str());
}

TEST_CASE("table: modal vs oversampled explicit, impulse response of a 30-mass membrane") {
    std::string table =
        "\n| damping | explicit oversampling | rel. RMS diff, position | rel. RMS diff, net force |\n"
        "|---|---|---|---|\n";
    for (bool damped : {true, false}) {
        const double alpha = damped ? 20.0 : 0.0, beta = damped ? 2e-6 : 0.0;
        auto modal_body = lattice_membrane(30, 0.06, 1000.0, alpha, beta);
        REQUIRE(modal_body.network.mass_count() >= 27);
        REQUIRE(modal_body.network.mass_count() <= 33);
        modal_body.network.finalize(kT, options_for(Integrator::modal));
        const int hit = 4, pick = modal_body.network.mass_count() - 3, samples = 4800;   // 0.1 s
        modal_body.network.apply_force(hit, 1.0);
        std::vector<double> xm, fm;
        for (int n = 0; n < samples; ++n) {
            fm.push_back(modal_body.network.step());
            xm.push_back(modal_body.network.position(pick));
        }
        for (int over : {1, 4, 16}) {
            CAPTURE(damped);
            CAPTURE(over);
            auto body = lattice_membrane(30, 0.06, 1000.0, alpha, beta);
            body.network.finalize(kT / over, options_for(Integrator::explicit_verlet));
            REQUIRE(body.network.stability().sub_steps == 1);
            // The same impulse 1 N * T at t = 0 (modal.hpp: the force is an impulse at the step's start):
            // over * 1 N for one fine step.
            body.network.apply_force(hit, static_cast<double>(over));
            double dx2 = 0.0, x2 = 0.0, df2 = 0.0, f2 = 0.0;
            for (int n = 0; n < samples; ++n) {
                double f = 0.0;
                for (int s = 0; s < over; ++s) f += body.network.step();
                f /= over;   // momentum change over the output step / T
                const double x = body.network.position(pick);
                dx2 += (x - xm[static_cast<std::size_t>(n)]) * (x - xm[static_cast<std::size_t>(n)]);
                x2 += x * x;
                df2 += (f - fm[static_cast<std::size_t>(n)]) * (f - fm[static_cast<std::size_t>(n)]);
                f2 += f * f;
            }
            const double ex = std::sqrt(dx2 / x2), ef = std::sqrt(df2 / f2);
            // Brief: 16x oversampled explicit vs modal, relative RMS difference < 1 %.
            if (over == 16) {
                CHECK(ex < 0.01);
                CHECK(ef < 0.01);
            }
            char line[256];
            std::snprintf(line, sizeof line, "| %s | %dx | %.2e | %.2e |\n", damped ? "Rayleigh 20 /s, 2e-6 s" : "none", over, ex, ef);
            table += line;
        }
    }
    if (print_tables()) std::printf("%s", table.c_str());
}
