// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The two charts of `ameoto bench accuracy`, as self-contained SVG (no scripts, fonts or images):
// cost against error on log-log axes with the Pareto front, and the stability map.
//
// Interface:
//   LogPanel p{"frequency error (cents)", points};            // one point per method, labelled
//   std::string svg = cost_error_chart(title, {p1, p2});      // two panels a row, cost (p.x_label) on x
//   StabilitySeries s{"explicit Verlet", omega_t, measured, theory};
//   std::string svg = stability_chart(title, {s, ...});       // growth per step against omega_max T
//
// Cost-error: x and y logarithmic over the data's decades; each point a marker with its label; the
// Pareto front (points with front = true, cheapest first) joined by a staircase: a method off the front
// is beaten by one on it in both cost and error. Errors below `floor` (exact methods) are drawn at the
// floor with a downward arrow. Stability: growth factor per step on a log y axis (0.5 to 10), omega_max
// T on a log x axis (0.1 to 10); measured values as markers, the theoretical bound as a line in the
// same colour, and the explicit schemes' limit omega T = 2 as a dashed vertical line.

#include <string>
#include <vector>

namespace ameoto::client {

struct ChartPoint {
    std::string label;    // empty: the marker alone (a cluster named by one of its points)
    double cost = 0.0;    // ns per sample
    double error = 0.0;
    bool front = false;
    std::string colour;   // the marker's fill; empty: green on the front, blue off it
};

struct LogPanel {
    std::string y_label;
    std::vector<ChartPoint> points;
    double floor = 1e-3;  // errors below are drawn here
    // The drop tiers' panel measures cost per drop, not per sample, and its exact point is a reference.
    std::string x_label = "cost, ns per output sample of one panel (log)";
    std::string floor_note = "at the floor with an arrow: error 0 (exact)";
    std::string omitted_note = "not drawn (modes left out, infinite error):";
    std::string heading;   // drawn above the panel when set
};

struct StabilitySeries {
    std::string name;
    std::vector<double> omega_t, measured, theory;
};

std::string cost_error_chart(const std::string& title, const std::vector<LogPanel>& panels);
std::string stability_chart(const std::string& title, const std::vector<StabilitySeries>& series);

}  // namespace ameoto::client
