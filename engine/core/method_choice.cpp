// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/method_choice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ameoto {

namespace {

// Modal rows keep audible modes only: the renderer hears a panel through its net force, and modes
// whose net-force weight is (numerically) zero, such as the antisymmetric modes of a symmetric panel,
// make no sound there (modal.hpp, mode selection).
constexpr double audible_weight = 1e-6;

std::string number(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.4g", v);
    return buffer;
}

bool better(const MeasuredMethod& a, const MeasuredMethod& b, AccuracyMeasure m) {
    if (a.ns_per_sample != b.ns_per_sample) return a.ns_per_sample < b.ns_per_sample;
    return a.error(m) < b.error(m);
}

}  // namespace

std::string method_label(const MethodSetting& s) {
    // Appended piece by piece: GCC 12's -Wrestrict misfires on `label += " " + std::to_string(n)`.
    std::string label = integrator_name(s.integrator);
    if (conditionally_stable(s.integrator)) label.append(" ").append(std::to_string(s.sub_steps)).append("x");
    if (s.integrator == Integrator::modal) {
        if (s.modes > 0) label.append(" ").append(std::to_string(s.modes)).append(" modes");
        else label.append(" all modes");
    }
    return label;
}

NetworkOptions network_options_for(const MethodSetting& s) {
    NetworkOptions o;
    o.integrator = s.integrator;
    o.stability.min_sub_steps = conditionally_stable(s.integrator) ? std::max(1, s.sub_steps) : 1;
    if (s.integrator == Integrator::modal) {
        o.modal.max_modes = std::max(0, s.modes);
        o.modal.min_net_force_weight = audible_weight;
    }
    return o;
}

const char* accuracy_measure_name(AccuracyMeasure m) { return m == AccuracyMeasure::cents ? "cents" : "db"; }

bool parse_accuracy_measure(const std::string& text, AccuracyMeasure& out) {
    if (text == "cents") out = AccuracyMeasure::cents;
    else if (text == "db") out = AccuracyMeasure::decibels;
    else return false;
    return true;
}

std::string validate_accuracy_budget(const AccuracyBudget& b) {
    const bool cents = b.measure == AccuracyMeasure::cents;
    const double lo = cents ? AccuracyLimits::cents_min : AccuracyLimits::decibels_min;
    const double hi = cents ? AccuracyLimits::cents_max : AccuracyLimits::decibels_max;
    if (!std::isfinite(b.value) || b.value < lo || b.value > hi)
        return std::string("accuracy budget must be ") + number(lo) + " to " + number(hi) + (cents ? " cents" : " dB");
    return {};
}

MethodChoice choose_method(const AccuracyBudget& budget, std::span<const MeasuredMethod> table) {
    MethodChoice c;
    const AccuracyMeasure m = budget.measure;
    const MeasuredMethod* best = nullptr;
    for (const MeasuredMethod& row : table)
        if (row.error(m) <= budget.value && (!best || better(row, *best, m))) best = &row;
    const char* unit = m == AccuracyMeasure::cents ? " cents" : " dB";
    if (best) {
        c.method = *best;
        c.meets_budget = true;
        c.reason = method_label(best->setting) + ": " + number(best->error(m)) + unit + " <= " + number(budget.value) + unit +
                   ", the cheapest such (" + number(best->ns_per_sample) + " ns/sample per panel)";
        return c;
    }
    for (const MeasuredMethod& row : table)
        if (!best || row.error(m) < best->error(m) || (row.error(m) == best->error(m) && row.ns_per_sample < best->ns_per_sample))
            best = &row;
    if (!best) return c;
    c.method = *best;
    c.reason = method_label(best->setting) + ": no method meets " + number(budget.value) + unit + "; the most accurate (" +
               number(best->error(m)) + unit + ")";
    return c;
}

std::vector<MeasuredMethod> pareto_front(std::span<const MeasuredMethod> table, AccuracyMeasure m) {
    std::vector<MeasuredMethod> rows(table.begin(), table.end());
    std::sort(rows.begin(), rows.end(), [m](const MeasuredMethod& a, const MeasuredMethod& b) { return better(a, b, m); });
    std::vector<MeasuredMethod> front;
    for (const MeasuredMethod& r : rows)   // cheapest first: kept when more accurate than every cheaper row
        if (std::isfinite(r.error(m)) && (front.empty() || r.error(m) < front.back().error(m))) front.push_back(r);
    return front;
}

}  // namespace ameoto
