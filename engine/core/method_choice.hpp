// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The accuracy knob: an accuracy budget (cents of frequency error, or dB of log-spectral distance) and
// the cheapest integration method that meets it, chosen from the measured speed/accuracy table.
//
// Interface:
//   AccuracyBudget b{AccuracyMeasure::cents, 5.0};          // or {AccuracyMeasure::decibels, 1.0}
//   MethodChoice c = choose_method(b);                      // from measured_methods() (method_table.cpp)
//   c.method.setting, c.method.ns_per_sample, c.meets_budget, c.reason
//   NetworkOptions o = network_options_for(c.method.setting);   // what the canopy's panels run
//   method_label(setting)                                   // "explicit Verlet 2x", "modal 16 modes"
//   pareto_front(table, measure)                            // rows no other row beats on cost and error
//   parse_accuracy_measure("cents") / accuracy_measure_name(AccuracyMeasure::cents)
//
// The table (method_table.cpp) is data measured by `ameoto bench accuracy --table FILE` on the default
// umbrella panel (50 masses, nylon, 48 kHz; docs/accuracy.md): cost in ns per output sample of one panel
// (thread CPU time, median of runs) and two errors against the exact modal solution: the largest
// frequency error of the panel's audible modes below 5 kHz (cents; a mode left out is infinite) and the log-spectral distance of its
// impulse response (net force, 20 Hz..20 kHz, dB). It is committed rather than measured at start-up
// because timing every method takes seconds of CPU and is noisy on a shared machine; only the ordering
// of costs matters for the choice, and that ordering is a property of the methods, not of the machine.
// Choice: among the rows whose error (in the budget's measure) is within the budget, the cheapest (ties:
// the more accurate). No row meets it: the most accurate row, meets_budget false (the reason says so).
// Tightening a budget never picks a less accurate row: the feasible set only shrinks, so the new choice
// is the old one or a row the old budget allowed whose error is below the new budget (tested).

#include <span>
#include <string>
#include <vector>

#include "engine/core/integrators/integrator.hpp"
#include "engine/core/transverse_network.hpp"

namespace ameoto {

enum class AccuracyMeasure { cents, decibels };

struct AccuracyBudget {
    AccuracyMeasure measure = AccuracyMeasure::cents;
    double value = 0.0;   // cents (frequency error) or dB (log-spectral distance); > 0
    bool operator==(const AccuracyBudget&) const = default;
};

// Ranges accepted at the boundary (scene files, OSC).
struct AccuracyLimits {
    static constexpr double cents_min = 0.001, cents_max = 1200.0;
    static constexpr double decibels_min = 0.001, decibels_max = 60.0;
};

struct MethodSetting {
    Integrator integrator = Integrator::explicit_verlet;
    int sub_steps = 1;   // explicit schemes: at least this many internal steps per output sample
    int modes = 0;       // modal: the lowest audible modes kept (0: every audible mode)
    bool operator==(const MethodSetting&) const = default;
};

struct MeasuredMethod {
    MethodSetting setting;
    double ns_per_sample = 0.0;   // one umbrella panel, per output sample
    double cents = 0.0;           // largest frequency error of the audible modes below 5 kHz
    double decibels = 0.0;        // log-spectral distance of the impulse response
    double error(AccuracyMeasure m) const { return m == AccuracyMeasure::cents ? cents : decibels; }
};

struct MethodChoice {
    MeasuredMethod method;
    bool meets_budget = false;
    std::string reason;   // "explicit Verlet 2x: 0.8 cents <= 5 cents, cheapest such (412 ns/sample)"
};

std::span<const MeasuredMethod> measured_methods();   // method_table.cpp
// Where the table came from (the command and the machine), for docs and /accuracy.
const char* measured_methods_source();

MethodChoice choose_method(const AccuracyBudget& budget, std::span<const MeasuredMethod> table = measured_methods());
std::vector<MeasuredMethod> pareto_front(std::span<const MeasuredMethod> table, AccuracyMeasure measure);

std::string method_label(const MethodSetting& setting);
NetworkOptions network_options_for(const MethodSetting& setting);
const char* accuracy_measure_name(AccuracyMeasure m);   // "cents", "db"
bool parse_accuracy_measure(const std::string& text, AccuracyMeasure& out);
// "" when valid; else why (value out of its measure's range, not finite).
std::string validate_accuracy_budget(const AccuracyBudget& budget);

}  // namespace ameoto
