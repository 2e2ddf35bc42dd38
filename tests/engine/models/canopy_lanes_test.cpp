// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/canopy's laned step (core/integrators/laned_network.hpp): a canopy stepped as
// lanes renders the bits of its panels stepped one TransverseNetwork at a time (how the canopy stepped
// before), down to the far field's pressures; the other integrators keep per-panel networks.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/models/canopy.hpp"
#include "engine/models/radiation.hpp"
#include "tests/support/test_constants.hpp"

using namespace ameoto::test::common;

namespace {

using ameoto::Canopy;
using ameoto::Integrator;
using ameoto::TransverseNetwork;

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

struct Mismatches {
    long compared = 0, differing = 0;
    void check(double a, double b) {
        ++compared;
        if (bits(a) != bits(b)) ++differing;
    }
};

std::vector<ameoto::RadiatingElement> panel_major_elements(const Canopy& canopy) {
    std::vector<ameoto::RadiatingElement> elements;
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i)
            elements.push_back({canopy.rest_position(k, i), canopy.normal(k, i), canopy.node_area(), k});
    return elements;
}

// The canopy and far field as they ran before the lanes: one TransverseNetwork per panel (copies of the
// canopy's own, which stay at rest when it is laned), each panel's velocities read in turn into a
// panel-major array of accelerations for a RayleighRadiator in the elements' own order, then the channel
// gains. Same formulas, step by step, as the code the lanes replaced.
struct PerPanelReference {
    std::vector<TransverseNetwork> panels;
    ameoto::RayleighRadiator radiator;
    ameoto::ListenerLayout layout;
    int nodes = 0;
    std::vector<double> previous, acceleration, sums;
    std::vector<std::uint64_t> resets_seen;

    PerPanelReference(const Canopy& canopy, const ameoto::ListenerLayout& l)
        : radiator(panel_major_elements(canopy), l.points, canopy.panel_count(), kT), layout(l), nodes(canopy.nodes_per_panel()) {
        for (int k = 0; k < canopy.panel_count(); ++k) panels.push_back(canopy.panel(k).network);
        previous.assign(panels.size() * static_cast<std::size_t>(nodes), 0.0);
        acceleration.assign(previous.size(), 0.0);
        sums.assign(l.points.size() * panels.size(), 0.0);
        resets_seen.assign(panels.size(), 0);
    }
    void far_field(double* out) {
        for (std::size_t k = 0; k < panels.size(); ++k) {
            const bool restarted = panels[k].guard_resets() != resets_seen[k];
            resets_seen[k] = panels[k].guard_resets();
            double* a = acceleration.data() + k * static_cast<std::size_t>(nodes);
            double* prev = previous.data() + k * static_cast<std::size_t>(nodes);
            panels[k].velocities(a);
            for (int i = 0; i < nodes; ++i) {
                const double v = a[i];
                a[i] = (v - (restarted ? 0.0 : prev[i])) * (1.0 / kT);
                prev[i] = v;
            }
        }
        radiator.process(acceleration.data(), sums.data());
        const auto p = panels.size();
        for (int c = 0; c < layout.channels(); ++c) {
            const double* row = sums.data() + static_cast<std::size_t>(layout.channel_point[static_cast<std::size_t>(c)]) * p;
            double s = 0.0;
            for (std::size_t k = 0; k < p; ++k)
                s += (layout.panel_gain.empty() ? 1.0 : layout.panel_gain[static_cast<std::size_t>(c)][k]) * row[k];
            out[c] = s;
        }
    }
};

// Strikes several panels (a few impacts, some large, one non-finite that the guard must reset) for
// `steps` samples, comparing every net force, node position and velocity, the displacement range and
// the far field's pressures, bit for bit, each sample.
Mismatches compare(int panels, Integrator integrator, int min_sub_steps, int ceiling, double curvature, int steps) {
    ameoto::NetworkOptions o;
    o.integrator = integrator;
    o.stability.min_sub_steps = min_sub_steps;
    Canopy canopy(ameoto::CanopyGeometry{panels, 0.5, 50, curvature}, ameoto::MembraneMaterial::nylon_canopy(), kT, o);
    REQUIRE(canopy.laned());
    canopy.set_kernel_ceiling(ceiling);
    REQUIRE(canopy.stability().sub_steps == min_sub_steps);
    std::vector<std::vector<double>> gains(2, std::vector<double>(static_cast<std::size_t>(panels)));
    for (int k = 0; k < panels; ++k) gains[0][static_cast<std::size_t>(k)] = gains[1][static_cast<std::size_t>(panels - 1 - k)] = 0.3 + 0.1 * k;
    const ameoto::ListenerLayout layout = curvature < 10.0 ? ameoto::ListenerLayout::ears({0.05, 0.0, -0.3}, 0.4)
                                                           : ameoto::ListenerLayout::panned({0.0, 0.1, -0.3}, gains);
    ameoto::FarFieldRadiation ff(canopy, layout, kT);
    PerPanelReference ref(canopy, layout);
    const int nodes = canopy.nodes_per_panel(), channels = layout.channels();
    std::vector<double> forces(static_cast<std::size_t>(panels)), out(static_cast<std::size_t>(channels)), expected(out.size());
    Mismatches m;
    for (int n = 0; n < steps; ++n) {
        if (n % 97 < 3) {
            const ameoto::CanopyHit hit{(n / 97) % panels, (11 * (n / 97) + n) % nodes};
            const double f = (n % 2 == 0 ? -0.3 : 0.05) * (1 + (n / 97) % 4);
            canopy.apply_force(hit, f);
            ref.panels[static_cast<std::size_t>(hit.panel)].apply_force(hit.node, f);
        }
        if (n == steps / 2) {   // a runaway panel: the guard resets it and only it
            canopy.apply_force({panels - 1, 3}, std::numeric_limits<double>::infinity());
            ref.panels.back().apply_force(3, std::numeric_limits<double>::infinity());
        }
        canopy.step(forces.data());
        for (int k = 0; k < panels; ++k) m.check(forces[static_cast<std::size_t>(k)], ref.panels[static_cast<std::size_t>(k)].step());
        ameoto::DisplacementRange expected_range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        for (int k = 0; k < panels; ++k) {
            for (int i = 0; i < nodes; ++i) {
                const double u = ref.panels[static_cast<std::size_t>(k)].position(i);
                m.check(canopy.displacement(k, i), u);
                m.check(canopy.normal_velocity(k, i), ref.panels[static_cast<std::size_t>(k)].velocity(i));
                expected_range.lowest = std::min(expected_range.lowest, u);
                expected_range.highest = std::max(expected_range.highest, u);
            }
        }
        const ameoto::DisplacementRange range = canopy.displacement_range();
        m.check(range.lowest, expected_range.lowest);
        m.check(range.highest, expected_range.highest);
        ff.process(canopy, out.data());
        ref.far_field(expected.data());
        for (int c = 0; c < channels; ++c) m.check(out[static_cast<std::size_t>(c)], expected[static_cast<std::size_t>(c)]);
        if (n % 64 == 63 || n == steps / 2 + 1) {   // the canopy's own guard cadence, once a block
            int expected_resets = 0;
            for (auto& p : ref.panels) expected_resets += p.guard() ? 1 : 0;
            CHECK(canopy.reset_unstable() == expected_resets);
            std::vector<double> u(static_cast<std::size_t>(nodes)), u_ref(u.size()), v(u.size()), v_ref(u.size());
            for (int k = 0; k < panels; ++k) {
                canopy.panel_positions(k, u.data());
                canopy.panel_velocities(k, v.data());
                ref.panels[static_cast<std::size_t>(k)].positions(u_ref.data());
                ref.panels[static_cast<std::size_t>(k)].velocities(v_ref.data());
                for (std::size_t i = 0; i < u.size(); ++i) {
                    m.check(u[i], u_ref[i]);
                    m.check(v[i], v_ref[i]);
                }
                CHECK(canopy.panel_guard_resets(k) == ref.panels[static_cast<std::size_t>(k)].guard_resets());
                CHECK(canopy.panel_finite(k) == ref.panels[static_cast<std::size_t>(k)].finite());
                m.check(canopy.panel_energy(k), ref.panels[static_cast<std::size_t>(k)].kinetic_plus_potential_energy());
            }
        }
    }
    CHECK(canopy.panel_guard_resets(panels - 1) == 1);
    return m;
}

}  // namespace

TEST_CASE("canopy lanes: bit-identical to per-panel networks, far field included") {
    // Explicit Verlet (the live default) and symplectic Euler; one and three sub-steps; 6, 7 (not
    // multiples of 4: padded lanes) and 8 panels; flat and curved; the baseline, AVX2 and AVX-512 kernels
    // (each where the CPU has it; AVX-512 for 8 padded lanes, so all three panel counts).
    for (Integrator integrator : {Integrator::explicit_verlet, Integrator::symplectic_euler}) {
        for (int sub_steps : {1, 3}) {
            for (int panels : {6, 7, 8}) {
                for (int ceiling : {16, 32, 64}) {
                    CAPTURE(std::string(ameoto::integrator_name(integrator)));
                    CAPTURE(sub_steps);
                    CAPTURE(panels);
                    CAPTURE(ceiling);
                    const double curvature = panels == 7 ? 1.5 : std::numeric_limits<double>::infinity();
                    const Mismatches m = compare(panels, integrator, sub_steps, ceiling, curvature, 1500);
                    CHECK(m.compared > 1500L * panels * 100);
                    CHECK(m.differing == 0);
                }
            }
        }
    }
}

TEST_CASE("canopy lanes: the implicit and modal integrators keep per-panel networks") {
    for (Integrator integrator : {Integrator::trapezoidal, Integrator::backward_euler, Integrator::modal}) {
        CAPTURE(std::string(ameoto::integrator_name(integrator)));
        ameoto::NetworkOptions o;
        o.integrator = integrator;
        Canopy canopy(ameoto::CanopyGeometry{6, 0.5, 30}, ameoto::MembraneMaterial::nylon_canopy(), kT, o);
        CHECK_FALSE(canopy.laned());
        CHECK(canopy.lanes() == 8);
        std::vector<double> forces(6), v(static_cast<std::size_t>(8 * canopy.nodes_per_panel())), one(static_cast<std::size_t>(canopy.nodes_per_panel()));
        canopy.apply_force({4, 5}, 0.2);
        for (int n = 0; n < 5; ++n) canopy.step(forces.data());
        canopy.velocities(v.data());
        canopy.panel_velocities(4, one.data());
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            CHECK(bits(v[static_cast<std::size_t>(i * 8 + 4)]) == bits(one[static_cast<std::size_t>(i)]));
            CHECK(v[static_cast<std::size_t>(i * 8 + 7)] == 0.0);   // padding
        }
        CHECK(canopy.displacement(4, 5) == canopy.panel(4).network.position(5));
        CHECK(canopy.displacement(4, 5) != 0.0);
    }
}

TEST_CASE("canopy lanes: the default canopy is laned") {
    const Canopy canopy(ameoto::CanopyGeometry{}, ameoto::MembraneMaterial::nylon_canopy(), kT);
    CHECK(canopy.laned());
    CHECK(canopy.lanes() == 8);
}
