// SPDX-License-Identifier: GPL-3.0-or-later
// `ameoto bench accuracy`'s canopy in air (clients/ameoto/bench_accuracy_air.hpp): the error measure
// against known perturbations, and the rows held to the FDTD reference's committed figures. About 4 s of
// CPU in Release (the scene's air modes are built once, ~1.6 s; the reference's cost runs on a 50 mm grid).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "clients/ameoto/bench_accuracy_air.hpp"
#include "engine/models/canopy.hpp"

using namespace ameoto;
using namespace ameoto::client;

namespace {

const BenchMesh& air_test_panel() {
    static const BenchMesh mesh = canopy_panel_mesh(CanopyGeometry{}.masses_per_panel);
    return mesh;
}

const AccuracyReference& air_test_exact() {
    static const AccuracyReference r = make_reference(air_test_panel(), pitch_band_hz);
    return r;
}

const AirModels& air_test_models() {
    static const AirModels m = build_air_models();
    return m;
}

// The models' panel modes by the estimator, computed once for the file (each a modal superposition of
// 400 modes over 100 ms).
const std::vector<double>& air_test_air_hz() {
    static const std::vector<double> hz = air_model_panel_modes(air_test_models());
    return hz;
}

const std::vector<double>& air_test_vacuum_hz() {
    static const std::vector<double> hz = vacuum_panel_modes(air_test_models());
    return hz;
}

std::vector<double> air_test_shifted(const std::vector<double>& hz, double cents) {
    std::vector<double> out;
    for (double f : hz) out.push_back(f * std::pow(2.0, cents / 1200.0));
    return out;
}

}  // namespace

TEST_CASE("bench accuracy in air: the error measure against known perturbations") {
    const std::vector<double> ref = cached_air_reference().mode_hz;
    REQUIRE(ref.size() == static_cast<std::size_t>(air_panel_modes));
    // Against itself: 0 in every mode.
    CHECK(in_air_errors(ref, ref).worst == 0.0);
    // Every mode 10 cents sharp: 10 cents each (to rounding, 1e-9 cents).
    const AirModeErrors sharp = in_air_errors(air_test_shifted(ref, 10.0), ref);
    for (double c : sharp.cents) CHECK(c == doctest::Approx(10.0).epsilon(1e-9));
    CHECK(sharp.worst == doctest::Approx(10.0).epsilon(1e-9));
    // One mode 25 cents flat among 10 sharp: the worst is its 25, signed per mode.
    std::vector<double> mixed = air_test_shifted(ref, 10.0);
    mixed[3] = ref[3] * std::pow(2.0, -25.0 / 1200.0);
    const AirModeErrors m = in_air_errors(mixed, ref);
    CHECK(m.cents[3] == doctest::Approx(-25.0).epsilon(1e-9));
    CHECK(m.worst == doctest::Approx(25.0).epsilon(1e-9));
    // A mode the model does not have: infinite.
    mixed[9] = 0.0;
    CHECK(std::isinf(in_air_errors(mixed, ref).worst));
    CHECK_THROWS_AS(in_air_errors({100.0}, ref), std::invalid_argument);
    CHECK_THROWS_AS(in_air_errors({100.0}, {0.0}), std::invalid_argument);
    CHECK_THROWS_AS(compute_air_reference(0.0), std::invalid_argument);
}

TEST_CASE("bench accuracy in air: the models by the reference's estimator") {
    const std::vector<double> ref = cached_air_reference().mode_hz;
    // The exact in-vacuum canopy, through the same estimator, gives the panel's own vacuum modes (the
    // ones the panel chart measures each method against): the rows' per-mode ratios apply to the right
    // modes. Within 5 cents: a single damped mode's windowed peak (0.1 s Hann, refined) against its
    // zero crossings; measured under 1 cent.
    const std::vector<double>& vacuum = air_test_vacuum_hz();
    REQUIRE(vacuum.size() == ref.size());
    for (std::size_t q = 0; q < vacuum.size(); ++q) {
        const double c = 1200.0 * std::log2(vacuum[q] / air_test_exact().mode_hz[q]);
        std::printf("panel mode %zu: in vacuum %.2f Hz by the estimator, %.2f Hz exact (%+.3f cents)\n", q + 1, vacuum[q],
                    air_test_exact().mode_hz[q], c);
        CHECK(std::abs(c) < 5.0);
    }
    const AirModeErrors vac = in_air_errors(vacuum, ref);
    const AirModeErrors air = in_air_errors(air_test_air_hz(), ref);
    std::printf("in air against the reference: air-loaded worst %.1f cents, in vacuum worst %.1f cents (mode 1 %+.1f)\n", air.worst,
                vac.worst, vac.cents[0]);
    // The air-loaded model: issue 19's 3 % (51.2 cents) in every mode, as
    // tests/engine/reference/canopy_modes_test.cpp holds it (mode 4 -2.2 %, 38 cents, the worst).
    CHECK(air.worst < 1200.0 * std::log2(1.03));
    // Leaving the air out: every mode sharp by the air's mass, the lowest by most of an octave
    // (217.2 Hz against 122.2 Hz, 995 cents; acoustics.md section 1: 1.1-1.6 octaves for the longest).
    for (double c : vac.cents) CHECK(c > 400.0);
    CHECK(vac.worst > 10.0 * air.worst);
}

TEST_CASE("bench accuracy in air: the rows, held to the reference's figures") {
    const AirReference reference = cached_air_reference();
    std::vector<AccuracyRow> vacuum_rows;
    for (const MethodSetting& s : {MethodSetting{Integrator::explicit_verlet, 1, 0}, MethodSetting{Integrator::modal, 1, 8}}) {
        AccuracyRow r;
        r.body = air_test_panel().name;
        r.method.setting = s;
        r.method.ns_per_sample = 400.0;   // a stand-in cost: only the errors are checked here
        r.errors = measure_errors(air_test_panel(), s, air_test_exact());
        vacuum_rows.push_back(r);
    }
    // A method whose every mode is exactly 20 cents sharp of the exact vacuum solution.
    AccuracyRow sharp = vacuum_rows.front();
    sharp.method.setting = MethodSetting{Integrator::trapezoidal, 1, 0};
    sharp.method.ns_per_sample = 500.0;
    sharp.errors.mode_hz = air_test_shifted(air_test_exact().mode_hz, 20.0);
    vacuum_rows.push_back(sharp);
    AirRowOptions options;
    options.seconds = 0.02;
    options.runs = 1;
    options.cost_dx_m = 0.05;           // the cost alone, on a coarse grid (a fraction of a second)
    options.cost_duration_s = 0.002;
    const std::vector<AirRow> rows = measure_air_rows(reference, vacuum_rows, air_test_exact(), options, &air_test_models());
    REQUIRE(rows.size() == 2 + vacuum_rows.size());
    const AirRow& ref = rows[0];
    const AirRow& air = rows[1];
    CHECK(ref.kind == "reference");
    CHECK(ref.errors.worst == 0.0);        // 0 by definition
    CHECK(ref.ns_per_sample > 0.0);
    CHECK(ref.front);                      // the slow, accurate end
    CHECK(air.kind == "air");
    CHECK(air.modes > 0);
    CHECK(air.ns_per_sample > 0.0);
    CHECK(air.ns_per_sample < ref.ns_per_sample);
    CHECK(air.errors.worst == doctest::Approx(in_air_errors(air_test_air_hz(), reference.mode_hz).worst));
    const std::vector<double>& vacuum = air_test_vacuum_hz();
    const AirModeErrors exact_vacuum = in_air_errors(vacuum, reference.mode_hz);
    // Explicit Verlet 1x: finite, its own 2.5 cents at most on top of the vacuum canopy's error.
    const AirRow& verlet = rows[2];
    CHECK(verlet.kind == "vacuum");
    CHECK(verlet.ns_per_sample == doctest::Approx(8 * 400.0));   // 8 panels
    CHECK(std::abs(verlet.errors.worst - exact_vacuum.worst) <= vacuum_rows[0].errors.cents + 1e-9);
    // Modal with 8 modes has no panel modes 9 and 10: infinite, off every front.
    CHECK(std::isinf(rows[3].errors.worst));
    CHECK_FALSE(rows[3].front);
    // The known perturbation: each mode's in-air error is the exact vacuum canopy's plus 20 cents.
    for (std::size_t q = 0; q < vacuum.size(); ++q) CHECK(rows[4].errors.cents[q] == doctest::Approx(exact_vacuum.cents[q] + 20.0).epsilon(1e-9));
    // Every in-vacuum row is further from the reference than the air-loaded model.
    for (std::size_t i = 2; i < rows.size(); ++i) CHECK(rows[i].errors.worst > air.errors.worst);
    CHECK(air.front);
}
