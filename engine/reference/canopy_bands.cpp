// SPDX-License-Identifier: GPL-3.0-or-later
// Fast model against reference in band levels: see canopy_bands.hpp.
#include "engine/reference/canopy_bands.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_canopy.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/dipole_radiation.hpp"

namespace ameoto::reference {

namespace {

// The struck node's force at time t: the pulse, or the given samples (linear between, 0 after).
double strike_force(const CanopyInAirSetup& s, double t) {
    if (!s.force_samples.empty()) {
        const double at = t / s.force_interval_s;
        const auto i = static_cast<std::size_t>(at);
        const double frac = at - static_cast<double>(i);
        const std::vector<double>& f = s.force_samples;
        if (i + 1 < f.size()) return f[i] + frac * (f[i + 1] - f[i]);
        return i < f.size() ? f[i] * (1.0 - frac) : 0.0;
    }
    return t < s.pulse_s ? s.force_n * 0.5 * (1.0 - std::cos(2.0 * constants::pi * t / s.pulse_s)) : 0.0;
}

}  // namespace

NodeForcesOnAir node_forces_on_air(const Canopy& canopy, const CanopyInAirResult& run) {
    NodeForcesOnAir out;
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            out.positions.push_back(canopy.rest_position(k, i));
            out.normals.push_back(canopy.normal(k, i));
            std::vector<double> f = run.node_air_force[static_cast<std::size_t>(k * canopy.nodes_per_panel() + i)];
            for (double& v : f) v = -v;   // the air's force on the node, reversed: the node's on the air
            out.force.push_back(std::move(f));
        }
    return out;
}

CanopyBandsResult compare_canopy_bands(const CanopyBandsSetup& setup) {
    if (setup.listeners.empty()) throw std::invalid_argument("compare_canopy_bands: no listener");
    CanopyInAirSetup s = setup.reference;
    s.record_forces = true;
    s.record_nodes = false;
    s.record_every = 1;
    // The box's own pressure for the points inside it (its interior, not its absorbing layers).
    const double half = s.geometry.radius_m + s.margin_m, z_margin = s.z_margin_m >= 0.0 ? s.z_margin_m : s.margin_m;
    CanopyBandsResult out;
    std::vector<int> box_index(setup.listeners.size(), -1);
    s.listeners.clear();
    for (std::size_t l = 0; l < setup.listeners.size(); ++l) {
        const Vec3 p = setup.listeners[l];
        const bool inside = std::abs(p.x) < half && std::abs(p.y) < half && std::abs(p.z) < z_margin && std::abs(p.z) >= s.dx;
        out.inside_box.push_back(inside);
        if (inside) {
            box_index[l] = static_cast<int>(s.listeners.size());
            s.listeners.push_back(p);
        }
    }
    const auto t0 = std::chrono::steady_clock::now();
    const CanopyInAirResult r = run_canopy_in_air(s);
    out.reference_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.struck_node = r.struck_node;
    const Canopy vacuum(s.geometry, s.material, 1.0 / setup.fast_rate_hz);
    const NodeForcesOnAir nodes = node_forces_on_air(vacuum, r);
    const auto& positions = nodes.positions;
    const auto& normals = nodes.normals;
    const auto& on_air = nodes.force;
    const int samples = static_cast<int>(r.node_air_force.front().size());
    for (std::size_t l = 0; l < setup.listeners.size(); ++l) {
        const std::vector<double> p = box_index[l] >= 0 ? r.pressure[static_cast<std::size_t>(box_index[l])]
                                                        : double_layer_pressure(on_air, positions, normals, r.sample_interval_s,
                                                                                setup.listeners[l], constants::speed_of_sound_air, samples);
        out.reference.push_back(third_octave_levels(p, r.sample_interval_s, setup.low_hz, setup.high_hz, setup.bands));
        out.reference_pressure.push_back(p);
    }
    out.reference_interval_s = r.sample_interval_s;

    FastCanopyBands fast = fast_canopy_bands(setup, r.struck_node);
    out.fast = std::move(fast.fast);
    out.fast_push = std::move(fast.fast_push);
    out.fast_pressure = std::move(fast.fast_pressure);
    out.fast_push_pressure = std::move(fast.fast_push_pressure);
    return out;
}

FastCanopyBands fast_canopy_bands(const CanopyBandsSetup& setup, int node) {
    Canopy canopy(setup.reference.geometry, setup.reference.material, 1.0 / setup.fast_rate_hz);
    canopy.set_air(build_air_canopy_modes(canopy, 1.0 / setup.fast_rate_hz));
    return fast_canopy_bands(setup, canopy, node);
}

FastCanopyBands fast_canopy_bands(const CanopyBandsSetup& setup, const Canopy& canopy, int node) {
    const CanopyInAirSetup& s = setup.reference;
    if (canopy.air_modes() == nullptr) throw std::invalid_argument("fast_canopy_bands: the canopy is not in air");
    if (s.panel < 0 || s.panel >= canopy.panel_count() || node < 0 || node >= canopy.nodes_per_panel())
        throw std::invalid_argument("fast_canopy_bands: the struck panel or node does not exist");
    // The fast model: the same force on the same node, its mean over each step (at the step's middle).
    const double dt = 1.0 / setup.fast_rate_hz;
    if (std::abs(canopy.air_modes()->time_step_s / dt - 1.0) > 1e-9)
        throw std::invalid_argument("fast_canopy_bands: the canopy's air is built for another rate");
    ListenerLayout layout;
    layout.points = setup.listeners;
    for (std::size_t l = 0; l < setup.listeners.size(); ++l) layout.channel_point.push_back(static_cast<int>(l));
    const auto steps = static_cast<long>(s.duration_s * setup.fast_rate_hz);
    auto play = [&](const DipoleOptions& options, std::vector<std::vector<double>>& heard) {
        Canopy struck(canopy);   // a copy never stepped: each run starts from rest
        DipoleRadiation dipole(struck, layout, dt, AirMedium{}, options);
        std::vector<std::vector<double>> fast(setup.listeners.size(), std::vector<double>(static_cast<std::size_t>(steps)));
        std::vector<double> panel_forces(static_cast<std::size_t>(struck.panel_count())), p(setup.listeners.size());
        for (long n = 0; n < steps; ++n) {
            const double f = strike_force(s, (static_cast<double>(n) + 0.5) * dt);
            if (f != 0.0) struck.apply_force({s.panel, node}, f);
            struck.step(panel_forces.data());
            dipole.process(struck, p.data());
            for (std::size_t l = 0; l < p.size(); ++l) fast[l][static_cast<std::size_t>(n)] = p[l];
        }
        std::vector<std::vector<BandLevel>> levels;
        for (const auto& x : fast) levels.push_back(third_octave_levels(x, dt, setup.low_hz, setup.high_hz, setup.bands));
        heard = std::move(fast);
        return levels;
    };
    FastCanopyBands out;
    out.fast = play(DipoleOptions{}, out.fast_pressure);
    out.fast_push = play(DipoleOptions{.compressible_push = true}, out.fast_push_pressure);
    return out;
}

}  // namespace ameoto::reference
