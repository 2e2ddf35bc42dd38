// SPDX-License-Identifier: GPL-3.0-or-later
// The accuracy knob (method_choice.hpp): the cheapest method within the budget, never a less accurate
// one for a tighter budget, the Pareto front, and the options each setting builds. The choice made from
// the committed table is measured against its budget in tests/clients/bench_accuracy_test.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "engine/core/method_choice.hpp"
#include "engine/core/triangular_lattice.hpp"

using namespace ameoto;

namespace {

// A table with rows off the front (backward Euler: dearer and worse than trapezoidal; modal 8: as dear as
// explicit 2x and worse in dB) and a tie in cost.
const std::vector<MeasuredMethod> synthetic = {
    {{Integrator::explicit_verlet, 1, 0}, 100.0, 20.0, 3.0},
    {{Integrator::explicit_verlet, 2, 0}, 200.0, 5.0, 1.0},
    {{Integrator::trapezoidal, 1, 0}, 400.0, 8.0, 0.5},
    {{Integrator::backward_euler, 1, 0}, 450.0, 300.0, 12.0},
    {{Integrator::modal, 1, 8}, 200.0, 0.0, 4.0},
    {{Integrator::modal, 1, 0}, 800.0, 0.0, 0.0},
};

std::vector<double> budgets(double from, double to) {
    std::vector<double> b;
    for (int i = 0; i <= 60; ++i) b.push_back(from * std::pow(to / from, i / 60.0));
    return b;
}

void check_monotonic(std::span<const MeasuredMethod> table, AccuracyMeasure m, double loosest, double tightest) {
    double previous_error = INFINITY, previous_cost = 0.0;
    for (double b : budgets(loosest, tightest)) {   // loosest first
        CAPTURE(b);
        const MethodChoice c = choose_method({m, b}, table);
        // Tightening never picks a less accurate method, and never a cheaper one.
        CHECK(c.method.error(m) <= previous_error);
        CHECK(c.method.ns_per_sample >= previous_cost);
        if (c.meets_budget) CHECK(c.method.error(m) <= b);
        previous_error = c.method.error(m);
        previous_cost = c.method.ns_per_sample;
    }
}

}  // namespace

TEST_CASE("method choice: the cheapest method within the budget") {
    MethodChoice c = choose_method({AccuracyMeasure::cents, 10.0}, synthetic);
    CHECK(c.meets_budget);
    // explicit 2x and modal 8 cost the same: the more accurate wins the tie.
    CHECK(c.method.setting == MethodSetting{Integrator::modal, 1, 8});
    c = choose_method({AccuracyMeasure::cents, 50.0}, synthetic);
    CHECK(c.method.setting == MethodSetting{Integrator::explicit_verlet, 1, 0});
    c = choose_method({AccuracyMeasure::decibels, 1.5}, synthetic);
    CHECK(c.method.setting == MethodSetting{Integrator::explicit_verlet, 2, 0});
    c = choose_method({AccuracyMeasure::decibels, 0.5}, synthetic);
    CHECK(c.method.setting == MethodSetting{Integrator::trapezoidal, 1, 0});
    c = choose_method({AccuracyMeasure::decibels, 0.4}, synthetic);
    CHECK(c.method.setting == MethodSetting{Integrator::modal, 1, 0});
    CHECK(c.reason.find("modal all modes") == 0);
}

TEST_CASE("method choice: no method meets the budget -> the most accurate, and it says so") {
    const std::vector<MeasuredMethod> coarse(synthetic.begin(), synthetic.begin() + 4);
    const MethodChoice c = choose_method({AccuracyMeasure::cents, 1.0}, coarse);
    CHECK_FALSE(c.meets_budget);
    CHECK(c.method.setting == MethodSetting{Integrator::explicit_verlet, 2, 0});
    CHECK(c.reason.find("no method meets 1 cents") != std::string::npos);
}

TEST_CASE("method choice: tightening the budget never picks a less accurate method (synthetic and committed tables)") {
    check_monotonic(synthetic, AccuracyMeasure::cents, 1000.0, 0.001);
    check_monotonic(synthetic, AccuracyMeasure::decibels, 60.0, 0.001);
    REQUIRE(measured_methods().size() >= 8u);
    check_monotonic(measured_methods(), AccuracyMeasure::cents, 1200.0, 0.001);
    check_monotonic(measured_methods(), AccuracyMeasure::decibels, 60.0, 0.001);
}

TEST_CASE("method choice: the Pareto front") {
    const auto front = pareto_front(synthetic, AccuracyMeasure::decibels);
    // Cheapest first, each more accurate than every cheaper one.
    REQUIRE(front.size() == 4u);
    CHECK(front[0].setting == MethodSetting{Integrator::explicit_verlet, 1, 0});
    CHECK(front[1].setting == MethodSetting{Integrator::explicit_verlet, 2, 0});
    CHECK(front[2].setting == MethodSetting{Integrator::trapezoidal, 1, 0});   // dearer, but 0.5 dB < 1: on it
    CHECK(front[3].setting == MethodSetting{Integrator::modal, 1, 0});
    // Whatever the budget, the choice is on the front.
    for (double b : budgets(60.0, 0.001)) {
        const MethodChoice c = choose_method({AccuracyMeasure::decibels, b}, synthetic);
        bool on_front = false;
        for (const auto& f : front) on_front |= f.setting == c.method.setting;
        CHECK(on_front);
    }
}

TEST_CASE("method choice: labels, names and budget validation") {
    CHECK(method_label({Integrator::explicit_verlet, 4, 0}) == "explicit Verlet 4x");
    CHECK(method_label({Integrator::modal, 1, 16}) == "modal 16 modes");
    CHECK(method_label({Integrator::modal, 1, 0}) == "modal all modes");
    CHECK(method_label({Integrator::trapezoidal, 1, 0}) == "trapezoidal");
    AccuracyMeasure m{};
    CHECK(parse_accuracy_measure("db", m));
    CHECK(m == AccuracyMeasure::decibels);
    CHECK(parse_accuracy_measure("cents", m));
    CHECK(m == AccuracyMeasure::cents);
    CHECK_FALSE(parse_accuracy_measure("dB ", m));
    CHECK(validate_accuracy_budget({AccuracyMeasure::cents, 5.0}).empty());
    CHECK_FALSE(validate_accuracy_budget({AccuracyMeasure::cents, 0.0}).empty());
    CHECK_FALSE(validate_accuracy_budget({AccuracyMeasure::decibels, 61.0}).empty());
    CHECK_FALSE(validate_accuracy_budget({AccuracyMeasure::decibels, NAN}).empty());
}

TEST_CASE("method choice: each setting builds what it names on a membrane") {
    const std::vector<PolygonEdge> outline = {{{0.0, 0.0}, false}, {{0.2, 0.0}, true}, {{0.1, 0.17}, true}};
    const TriangularLattice lattice = build_triangular_lattice(outline, spacing_for_node_count(outline, 50));
    auto build = [&](const MethodSetting& s) {
        TransverseNetwork net;
        for (std::size_t i = 0; i < lattice.nodes.size(); ++i) {
            const int node = net.add_mass(1e-4, 0.0);
            if (lattice.anchor_links[i] > 0) net.add_anchor(node, lattice.anchor_links[i] * 50.0, 0.0);
        }
        for (const auto& l : lattice.links) net.add_link(l.a, l.b, 50.0, 0.0);
        net.finalize(1.0 / 48000.0, network_options_for(s));
        return net;
    };
    const TransverseNetwork e4 = build({Integrator::explicit_verlet, 4, 0});
    CHECK(e4.integrator() == Integrator::explicit_verlet);
    CHECK(e4.stability().sub_steps == 4);
    const TransverseNetwork m8 = build({Integrator::modal, 1, 8});
    CHECK(m8.integrator() == Integrator::modal);
    CHECK(m8.modal().mode_count() == 8);
    const TransverseNetwork all = build({Integrator::modal, 1, 0});
    CHECK(all.modal().mode_count() > 8);
    CHECK(all.modal().mode_count() <= all.mass_count());
    CHECK(build({Integrator::backward_euler, 1, 0}).integrator() == Integrator::backward_euler);
}
