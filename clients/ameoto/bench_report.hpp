// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One measurement of `ameoto bench engine`, and its two printed forms: a row of the text table and
// one JSON object on one line (docs/bench.md lists every field).
//
// Interface:
//   BenchMeasurement m;  m.mesh = "canopy panel"; m.method = "network explicit Verlet"; ...
//   m.ns_per_sample = 1234.5;                 // NaN: not measured (then m.note says why)
//   m.ns_per_mass_update()                    // ns per sample / (masses x sub-steps)
//   m.ns_per_link_update()                    // ns per sample / (links x sub-steps)
//   m.core_percent()                          // % of one core at the sample rate
//   m.realtime_factor()                       // sample period / ns per sample
//   std::string line = format_measurement_json(m);   // {"suite":"engine",...}\n
//   std::string head = format_table_header();        // column titles and a rule
//   std::string row = format_table_row(m);           // one aligned row (and its note)
//
// Per-mass and per-link figures divide the whole step's time (both loops) by the count: they are two
// views of one measurement, not separate timings. Non-finite numbers are written null in JSON.

#include <optional>
#include <string>

#include "clients/ameoto/json_text.hpp"

namespace ameoto::client {

struct BenchMeasurement {
    std::string mesh;            // "canopy panel", "mi-faust triangleMesh"
    std::string method;          // "network explicit Verlet", "grid explicit Verlet (float)", "faust"
    std::string body;            // "network", "grid", "faust"
    std::string integrator;      // "explicit Verlet", ...
    std::string precision;       // "double", "float"
    int target_masses = 0;       // what --sizes asked for (0: a fixed mesh)
    int masses = 0;              // moving masses
    int links = 0;               // springs between masses plus springs to fixed points
    int sub_steps = 1;
    double sample_rate_hz = 48000.0;
    double ns_per_sample = 0.0;  // median over runs; NaN when not measured
    double ns_min = 0.0, ns_max = 0.0;
    int runs = 0;
    long samples_per_run = 0;
    std::optional<double> faust_ratio;       // this method's ns per sample / Faust's (triangle mesh)
    std::optional<double> faust_difference;  // max |ours - Faust's| / max |Faust's| over the check
    std::string note;            // why not measured, or a remark

    bool measured() const;
    double ns_per_mass_update() const;
    double ns_per_link_update() const;
    double core_percent() const;
    double realtime_factor() const;
};

std::string format_measurement_json(const BenchMeasurement& m);
std::string format_table_header();
std::string format_table_row(const BenchMeasurement& m);

}  // namespace ameoto::client
