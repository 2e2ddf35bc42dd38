// SPDX-License-Identifier: GPL-3.0-or-later
// The umbrella canopy in air by the reference solver: see canopy_in_air.hpp.
#include "engine/reference/canopy_in_air.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <utility>

#include "engine/core/modal_decomposition.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/reference/air_solver.hpp"
#include "engine/reference/spectrum.hpp"

namespace ameoto::reference {

namespace {

struct CanopyStructure {
    ScreenStructure structure;
    int panels = 0, nodes = 0;
};

// The lattice of every panel as DOFs panel * nodes + node (Canopy's own numbering).
CanopyStructure canopy_structure(const Canopy& canopy, const MembraneMaterial& material) {
    CanopyStructure c;
    c.panels = canopy.panel_count();
    c.nodes = canopy.nodes_per_panel();
    const TriangularLattice& lattice = canopy.panel(0).lattice;
    const double node_mass = material.total_mass > 0.0 ? material.total_mass / static_cast<double>(c.nodes)
                                                       : material.areal_density * lattice.node_area;
    const double k = material.link_stiffness > 0.0 ? material.link_stiffness : material.tension / std::sqrt(3.0);
    // Rayleigh damping as in engine/models/membrane.hpp: alpha M + beta K (link_damping z given: beta = z / k).
    c.structure.mass_damping = material.mass_damping;
    c.structure.stiffness_damping = material.link_damping > 0.0 ? material.link_damping / k : material.stiffness_damping;
    for (int p = 0; p < c.panels; ++p) {
        const int base = p * c.nodes;
        for (int i = 0; i < c.nodes; ++i) {
            c.structure.add_dof(node_mass);
            const int anchors = lattice.anchor_links[static_cast<std::size_t>(i)];
            if (anchors > 0) c.structure.add_spring(base + i, -1, k * anchors);
        }
        for (const LatticeLink& l : lattice.links) c.structure.add_spring(base + l.a, base + l.b, k);
    }
    return c;
}

}  // namespace

CanopyInAirResult run_canopy_in_air(const CanopyInAirSetup& setup) {
    if (setup.geometry.curvature_radius_m < std::numeric_limits<double>::infinity())
        throw std::invalid_argument("run_canopy_in_air: only a flat canopy (the screen is one plane)");
    if (!(setup.duration_s > 0.0) || !(setup.pulse_s > 0.0) || setup.record_every < 1)
        throw std::invalid_argument("run_canopy_in_air: duration, pulse length and record_every must be positive");
    const double half = setup.geometry.radius_m + setup.margin_m;
    const double z_margin = setup.z_margin_m >= 0.0 ? setup.z_margin_m : setup.margin_m;
    const GridSpec g = GridSpec::box(setup.dx, half, half, z_margin, z_margin, setup.pml_cells);
    const double dt = g.time_step();
    const Canopy canopy(setup.geometry, setup.material, dt);
    CanopyStructure c = canopy_structure(canopy, setup.material);
    CanopyInAirResult r;
    r.panels = c.panels;
    r.nodes_per_panel = c.nodes;
    if (setup.panel < 0 || setup.panel >= c.panels || setup.node < -1 || setup.node >= c.nodes)
        throw std::invalid_argument("run_canopy_in_air: the struck panel or node does not exist");
    const Point2 centre = canopy.panel_centroid(setup.panel);
    r.struck_node = setup.node >= 0 ? setup.node : canopy.locate(centre.x, centre.y).node;
    const int struck = setup.panel * c.nodes + r.struck_node;

    AirSolver air(g, c.structure);
    std::vector<int> faces(static_cast<std::size_t>(c.structure.size()), 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const CanopyHit hit = canopy.locate(air.face_x(i), air.face_y(j));
            if (hit.panel < 0) continue;
            const int dof = hit.panel * c.nodes + hit.node;
            air.set_face(i, j, dof);
            ++faces[static_cast<std::size_t>(dof)];
        }
    r.nodes_without_faces = static_cast<int>(std::count(faces.begin(), faces.end(), 0));
    air.set_air_loading(setup.air);
    r.time_step_s = dt;
    r.sample_interval_s = dt * setup.record_every;
    r.sub_steps = air.structure().sub_steps();
    r.cells = static_cast<long>(air.cells());
    const long steps = static_cast<long>(std::ceil(setup.duration_s / dt));
    const std::size_t samples = static_cast<std::size_t>(steps / setup.record_every);
    r.pressure.assign(setup.listeners.size(), {});
    for (auto& p : r.pressure) p.reserve(samples);
    if (setup.record_nodes) {
        r.node_velocity.assign(static_cast<std::size_t>(c.structure.size()), {});
        for (auto& v : r.node_velocity) v.reserve(samples);
    }
    if (setup.record_forces) {
        r.node_air_force.assign(static_cast<std::size_t>(c.structure.size()), {});
        for (auto& v : r.node_air_force) v.reserve(samples);
    }
    if (!setup.force_samples.empty() && !(setup.force_interval_s > 0.0))
        throw std::invalid_argument("run_canopy_in_air: force samples need a positive interval");
    for (long n = 0; n < steps; ++n) {
        const double t = air.time();
        double f = t < setup.pulse_s ? setup.force_n * 0.5 * (1.0 - std::cos(2.0 * constants::pi * t / setup.pulse_s)) : 0.0;
        if (!setup.force_samples.empty()) {
            const double at = t / setup.force_interval_s;
            const auto i = static_cast<std::size_t>(at);
            const double frac = at - static_cast<double>(i);
            const std::vector<double>& fs = setup.force_samples;
            f = i + 1 < fs.size() ? fs[i] + frac * (fs[i + 1] - fs[i]) : (i < fs.size() ? fs[i] * (1.0 - frac) : 0.0);
        }
        air.set_external_force(struck, f);
        air.step();
        if ((n + 1) % setup.record_every) continue;
        for (std::size_t l = 0; l < setup.listeners.size(); ++l)
            r.pressure[l].push_back(air.pressure_at(setup.listeners[l].x, setup.listeners[l].y, setup.listeners[l].z));
        if (setup.record_nodes)
            for (int d = 0; d < c.structure.size(); ++d) r.node_velocity[static_cast<std::size_t>(d)].push_back(air.dof_velocity(d));
        if (setup.record_forces)
            for (int d = 0; d < c.structure.size(); ++d) r.node_air_force[static_cast<std::size_t>(d)].push_back(air.dof_air_force(d));
    }
    r.steps = air.steps();
    return r;
}

PanelProjections panel_projections_in_air(const CanopyInAirSetup& setup, int modes) {
    CanopyInAirSetup s = setup;
    s.record_every = 1;
    s.record_nodes = true;
    const GridSpec g = GridSpec::box(s.dx, 1.0, 1.0, 1.0, 1.0, s.pml_cells);
    const Canopy canopy(s.geometry, s.material, g.time_step());
    const CanopyStructure c = canopy_structure(canopy, s.material);
    // One panel's stiffness and mass (the panels are identical and, without air, independent).
    const int n = c.nodes;
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
    for (const Spring& sp : c.structure.springs) {
        if (sp.a >= n) continue;
        K(sp.a, sp.a) += sp.stiffness;
        if (sp.b >= 0) {
            K(sp.b, sp.b) += sp.stiffness;
            K(sp.a, sp.b) -= sp.stiffness;
            K(sp.b, sp.a) -= sp.stiffness;
        }
    }
    const double m = c.structure.mass[0];
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K / m);
    modes = std::clamp(modes, 1, n);
    const CanopyInAirResult r = run_canopy_in_air(s);
    PanelProjections out;
    out.sample_interval_s = r.sample_interval_s;
    for (int q = 0; q < modes; ++q) {
        out.vacuum_hz.push_back(std::sqrt(std::max(0.0, eig.eigenvalues()(q))) / (2.0 * constants::pi));
        std::vector<double> projection(r.node_velocity.front().size(), 0.0);
        for (int i = 0; i < n; ++i) {
            const double w = eig.eigenvectors()(i, q);
            const auto& v = r.node_velocity[static_cast<std::size_t>(s.panel * n + i)];
            for (std::size_t t = 0; t < v.size(); ++t) projection[t] += w * v[t];
        }
        out.velocity.push_back(std::move(projection));
    }
    return out;
}

std::vector<PanelMode> panel_modes_in_air(const CanopyInAirSetup& setup, int modes) {
    const PanelProjections p = panel_projections_in_air(setup, modes);
    std::vector<PanelMode> out;
    for (std::size_t q = 0; q < p.velocity.size(); ++q) {
        PanelMode mode;
        mode.vacuum_hz = p.vacuum_hz[q];
        mode.air_hz = panel_mode_frequency(p.velocity[q], p.sample_interval_s, mode.vacuum_hz, kPeakRecordS);
        out.push_back(mode);
    }
    return out;
}

PanelProjections modal_panel_projections(const CanopyInAirSetup& s, const Canopy& canopy, const AirLoadedModes& air, int modes) {
    const int nodes = canopy.nodes_per_panel();
    if (air.shapes.rows() != canopy.panel_count() * nodes)
        throw std::invalid_argument("modal_panel_modes: the modes are not the canopy's");
    if (s.panel < 0 || s.panel >= canopy.panel_count() || s.node < -1 || s.node >= nodes)
        throw std::invalid_argument("modal_panel_modes: the struck panel or node does not exist");
    const ModalDecomposition vac = decompose_modes(canopy.panel(0).network.arrays());
    const Point2 centre = canopy.panel_centroid(s.panel);
    const int struck = s.panel * nodes + (s.node >= 0 ? s.node : canopy.locate(centre.x, centre.y).node);
    modes = std::clamp(modes, 1, nodes);
    const double dt = 1.0 / 40000.0;
    const int steps = static_cast<int>(s.duration_s / dt);
    constexpr int quadrature = 40;
    // Each mode's velocity, v(t) = Re((1 + i s / w_d) e^(lambda t) F(t)), lambda = -s + i w_d, F(t) the
    // midpoint sum of f(tau) e^(-lambda tau) over the pulse's points before t (the impulse response's
    // convolution with the pulse, as one complex exponential): computed once per mode.
    const Eigen::Index count = air.omega.size();
    Eigen::MatrixXd velocity(steps, count);
    for (Eigen::Index m = 0; m < count; ++m) {
        const double sigma = air.damping_rate[m], w = air.omega[m];
        const double wd = std::sqrt(std::max(w * w - sigma * sigma, 1e-12));
        const std::complex<double> lambda(-sigma, wd), gain(1.0, sigma / wd);
        std::complex<double> f = 0.0;
        int k = 0;   // the pulse's points summed into f so far
        for (int t = 0; t < steps; ++t) {
            const double time = (t + 1) * dt;
            for (; k < quadrature; ++k) {
                const double tau = (k + 0.5) * s.pulse_s / quadrature;
                if (tau >= time) break;
                const double force = s.force_n * 0.5 * (1.0 - std::cos(2.0 * constants::pi * tau / s.pulse_s));
                f += force * std::exp(-lambda * tau);
            }
            velocity(t, m) = (gain * std::exp(lambda * time) * f).real() * s.pulse_s / quadrature;
        }
    }
    PanelProjections out;
    out.sample_interval_s = dt;
    for (int q = 0; q < modes; ++q) {
        // The struck panel's vacuum shape q against each mode, times the struck node's share of it.
        Eigen::VectorXd weight(count);
        for (Eigen::Index m = 0; m < count; ++m) {
            double sum = 0.0;
            for (int i = 0; i < nodes; ++i) sum += vac.shapes(i, q) * air.shapes(s.panel * nodes + i, m);
            weight[m] = sum * air.shapes(struck, m);
        }
        const Eigen::VectorXd p = velocity * weight;
        out.vacuum_hz.push_back(vac.omega[q] / (2.0 * constants::pi));
        out.velocity.emplace_back(p.data(), p.data() + p.size());
    }
    return out;
}

std::vector<double> modal_panel_modes(const CanopyInAirSetup& s, const Canopy& canopy, const AirLoadedModes& air, int modes) {
    const PanelProjections p = modal_panel_projections(s, canopy, air, modes);
    std::vector<double> out;
    for (std::size_t q = 0; q < p.velocity.size(); ++q)
        out.push_back(panel_mode_frequency(p.velocity[q], p.sample_interval_s, p.vacuum_hz[q], kPeakRecordS));
    return out;
}

double panel_mode_frequency(const std::vector<double>& projection, double dt, double vacuum_hz, double record_s) {
    const auto n = std::min(projection.size(), static_cast<std::size_t>(std::llround(record_s / dt)));
    const std::vector<double> head(projection.begin(), projection.begin() + static_cast<std::ptrdiff_t>(n));
    return peak_frequency(head, dt, 0.2 * vacuum_hz, 1.05 * vacuum_hz);
}

std::vector<DampedSinusoid> panel_mode_components(const std::vector<double>& projection, double dt, double vacuum_hz, double pulse_s) {
    PencilSettings p;
    p.f_lo_hz = 0.2 * vacuum_hz;
    p.f_hi_hz = 1.05 * vacuum_hz;
    p.start_s = pulse_s;
    p.relative_threshold = 1e-4;
    p.max_components = 400;
    return fit_damped_sinusoids(projection, dt, p);
}

}  // namespace ameoto::reference
