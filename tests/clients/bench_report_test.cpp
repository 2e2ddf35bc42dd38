// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_report: a measurement's derived figures, its JSON line and table row.
#include "clients/ameoto/bench_report.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>

using namespace ameoto::client;

namespace {

BenchMeasurement sample() {
    BenchMeasurement m;
    m.mesh = "canopy panel";
    m.method = "grid explicit Verlet (float)";
    m.body = "grid";
    m.integrator = "explicit Verlet";
    m.precision = "float";
    m.target_masses = 10000;
    m.masses = 10001;
    m.links = 29882;
    m.sub_steps = 2;
    m.sample_rate_hz = 48000.0;
    m.ns_per_sample = 10417.0;   // half of the 20 833 ns sample period
    m.ns_min = 10000.0;
    m.ns_max = 11000.0;
    m.runs = 5;
    m.samples_per_run = 8640;
    return m;
}

}  // namespace

TEST_CASE("bench report: derived figures") {
    const BenchMeasurement m = sample();
    CHECK(m.measured());
    CHECK(m.ns_per_mass_update() == ameoto::test::relative(10417.0 / (10001.0 * 2)));
    CHECK(m.ns_per_link_update() == ameoto::test::relative(10417.0 / (29882.0 * 2)));
    CHECK(m.core_percent() == doctest::Approx(50.0016));
    CHECK(m.realtime_factor() == doctest::Approx(1.99994).epsilon(1e-5));
}

TEST_CASE("bench report: one JSON object on one line, every field") {
    BenchMeasurement m = sample();
    m.faust_ratio = 0.3456;
    m.faust_difference = 2.5e-12;
    m.note = "a \"quoted\" note\n";
    CHECK(format_measurement_json(m) ==
          "{\"suite\":\"engine\",\"mesh\":\"canopy panel\",\"method\":\"grid explicit Verlet (float)\",\"body\":\"grid\","
          "\"integrator\":\"explicit Verlet\",\"precision\":\"float\",\"target_masses\":10000,\"masses\":10001,"
          "\"links\":29882,\"sub_steps\":2,\"sample_rate_hz\":48000,\"ns_per_sample\":10417,\"ns_per_sample_min\":10000,"
          "\"ns_per_sample_max\":11000,\"ns_per_mass_update\":0.520798,\"ns_per_link_update\":0.174302,"
          "\"core_percent\":50.0016,\"realtime_factor\":1.99994,\"runs\":5,\"samples_per_run\":8640,"
          "\"faust_ratio\":0.3456,\"faust_difference\":2.5e-12,\"note\":\"a \\\"quoted\\\" note\\u000a\"}\n");
}

TEST_CASE("bench report: what was not measured is null, never NaN") {
    BenchMeasurement m = sample();
    m.ns_per_sample = NAN;
    m.note = "skipped: too large";
    const std::string json = format_measurement_json(m);
    CHECK(json.find("nan") == std::string::npos);
    CHECK(json.find("inf") == std::string::npos);
    CHECK(json.find("\"ns_per_sample\":null") != std::string::npos);
    CHECK(json.find("\"realtime_factor\":null") != std::string::npos);
    CHECK(json.find("\"faust_ratio\":null") != std::string::npos);
    CHECK(json.find("\"runs\":0") != std::string::npos);
    CHECK(json_number(INFINITY) == "null");
    CHECK(json_number(-0.125) == "-0.125");
    CHECK(json_number(1234567.0) == "1.23457e+06");
    CHECK(json_string("tab\there") == "\"tab\\u0009here\"");
}

TEST_CASE("bench report: the table row lines up under the header") {
    BenchMeasurement m = sample();
    m.faust_ratio = 0.3456;
    const std::string header = format_table_header();
    const std::string row = format_table_row(m);
    const std::string first = header.substr(0, header.find('\n'));
    CHECK(row.substr(0, row.find('\n')).size() == first.size());
    CHECK(row.find("10417") != std::string::npos);
    CHECK(row.find("0.521") != std::string::npos);
    CHECK(row.find("2.00") != std::string::npos);
    CHECK(row.find("0.35") != std::string::npos);
    m.ns_per_sample = NAN;
    m.note = "skipped: dense modal decomposition, limited to 2500 masses";
    CHECK(format_table_row(m).find("not measured\n    skipped: dense modal") != std::string::npos);
}
