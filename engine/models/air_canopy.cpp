// SPDX-License-Identifier: GPL-3.0-or-later
// The canopy's air-loaded modes as resonators (air_canopy.hpp).
#include "engine/models/air_canopy.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "engine/core/integrators/mode_decay.hpp"
#include "engine/models/air_canopy_kernels.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto {

std::shared_ptr<const AirCanopyModes> build_air_canopy_modes(const Canopy& canopy, double time_step_s,
                                                             const AirCanopyOptions& o) {
    if (!(time_step_s > 0.0) || !std::isfinite(time_step_s)) throw std::invalid_argument("air canopy: the time step must be positive");
    if (!(o.air_density > 0.0 && o.air_density < 100.0)) throw std::invalid_argument("air canopy: air density outside 0..100 kg/m^3");
    if (!(o.speed_of_sound > 1.0 && o.speed_of_sound < 1e4)) throw std::invalid_argument("air canopy: speed of sound outside 1..1e4 m/s");
    if (!(o.max_frequency_hz > 0.0)) throw std::invalid_argument("air canopy: the cutoff must be positive");
    const AddedMass added = canopy_added_mass(canopy, o.air_density, o.air_mass);
    const AirLoadedModes all = air_loaded_modes(canopy, added);
    Eigen::VectorXd radiation = Eigen::VectorXd::Zero(all.omega.size());
    if (o.radiation_damping) radiation = ameoto::radiation_damping(all, added, o.air_density, o.speed_of_sound);

    auto m = std::make_shared<AirCanopyModes>();
    const auto n = static_cast<int>(all.omega.size());
    m->nodes = canopy.panel_count() * canopy.nodes_per_panel();
    m->modes_found = n;
    m->time_step_s = time_step_s;
    m->cutoff_hz = o.max_frequency_hz;
    std::vector<int> keep;
    for (int k = 0; k < n; ++k)   // ascending
        if (all.omega[k] <= 2.0 * constants::pi * o.max_frequency_hz) keep.push_back(k);
    const int kept = static_cast<int>(keep.size());
    m->modes = kept;
    m->omega.resize(kept);
    m->rate.resize(kept);
    m->radiation_rate.resize(kept);
    m->shape.assign(static_cast<std::size_t>(m->nodes) * static_cast<std::size_t>(kept), 0.0);
    m->air_force.resize(m->nodes, kept);
    const Eigen::MatrixXd force = added.matrix * all.shapes;
    for (int j = 0; j < kept; ++j) {
        const int k = keep[static_cast<std::size_t>(j)];
        m->omega[j] = all.omega[k];
        m->radiation_rate[j] = radiation[k];
        m->rate[j] = all.damping_rate[k] + radiation[k];
        for (int i = 0; i < m->nodes; ++i) m->shape[static_cast<std::size_t>(i) * kept + j] = all.shapes(i, k);
        m->air_force.col(j) = force.col(k);
        const ModeDecay d = mode_decay(m->omega[j], m->rate[j], time_step_s);   // integrators/mode_decay.hpp
        m->t11.push_back(d.ec + m->rate[j] * d.es);
        m->t12.push_back(d.es);
        m->t21.push_back(-m->omega[j] * m->omega[j] * d.es);
        m->t22.push_back(d.ec - m->rate[j] * d.es);
    }
    m->contact_mass.assign(static_cast<std::size_t>(m->nodes), 0.0);
    for (int i = 0; i < m->nodes; ++i) {
        double mobility = 0.0;
        for (int j = 0; j < kept; ++j) {
            const double phi = m->shape[static_cast<std::size_t>(i) * kept + j];
            mobility += phi * phi;
        }
        // With every mode dropped a node cannot move: an infinitely heavy contact.
        m->contact_mass[static_cast<std::size_t>(i)] = mobility > 0.0 ? 1.0 / mobility : 1e300;
    }
    m->largest_shape.assign(static_cast<std::size_t>(kept), 0.0);
    for (int i = 0; i < m->nodes; ++i)
        for (int j = 0; j < kept; ++j)
            m->largest_shape[static_cast<std::size_t>(j)] =
                std::max(m->largest_shape[static_cast<std::size_t>(j)], std::abs(m->shape[static_cast<std::size_t>(i) * kept + j]));
    m->node_area.assign(added.area.data(), added.area.data() + added.area.size());
    // (M + M_a)^-1 = Phi Phi' over the kept modes (Phi' (M + M_a) Phi = I), so M_a (M + M_a)^-1 = (M_a Phi) Phi'.
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> phi(m->shape.data(), m->nodes, kept);
    m->instantaneous_push = m->air_force * phi.transpose();
    return m;
}

void AirCanopyState::init(const AirCanopyModes& m) {
    const auto n = static_cast<std::size_t>(m.modes);
    q_.assign(n, 0.0);
    qd_.assign(n, 0.0);
    p_.assign(n, 0.0);
    a_.assign(n, 0.0);
    omega2_.resize(n);
    const auto nodes = static_cast<std::size_t>(m.nodes);
    u_.assign(nodes, 0.0);
    v_.assign(nodes, 0.0);
    u_stamp_.assign(nodes, 0);
    v_stamp_.assign(nodes, 0);
    for (Forces* f : {&pending_, &taken_}) {
        f->node.assign(nodes, 0);
        f->newtons.assign(nodes, 0.0);
        f->count = 0;
    }
    forced_stamp_.assign(nodes, 0);
    steps_ = 1;
    kernels_ = &air_kernels();   // chosen here, in the build phase: the first call initialises a static
    for (std::size_t k = 0; k < n; ++k) omega2_[k] = m.omega[static_cast<Eigen::Index>(k)] * m.omega[static_cast<Eigen::Index>(k)];
}

void AirCanopyState::step(const AirCanopyModes& m) {
    // The step's generalised forces, phi_k' f, one projection per forced node (apply_force gathers them).
    double* const p = p_.data();
    const int n = m.modes;
    for (int j = 0; j < pending_.count; ++j) {
        const auto i = static_cast<std::size_t>(pending_.node[static_cast<std::size_t>(j)]);
        const double f = pending_.newtons[i];
        const double* row = m.shape.data() + i * static_cast<std::size_t>(n);
        for (int k = 0; k < n; ++k) p[k] += f * row[k];
    }
    kernels_->advance(static_cast<std::size_t>(m.modes), q_.data(), qd_.data(), p_.data(), a_.data(), m.t11.data(), m.t12.data(),
                          m.t21.data(), m.t22.data(), m.time_step_s, 1.0 / m.time_step_s);
    std::swap(pending_, taken_);   // the vectors' buffers trade places: no allocation
    pending_.clear();
    ++steps_;
}

bool AirCanopyState::finite() const {
    double s = 0.0;
    for (std::size_t k = 0; k < q_.size(); ++k) s += q_[k] + qd_[k];
    return std::isfinite(s);
}

void AirCanopyState::reset() {
    for (auto* v : {&q_, &qd_, &p_, &a_})
        for (double& x : *v) x = 0.0;
    pending_.clear();
    taken_.clear();
    ++steps_;
}

double AirCanopyState::energy() const {
    double e = 0.0;
    for (std::size_t k = 0; k < q_.size(); ++k) e += qd_[k] * qd_[k] + omega2_[k] * q_[k] * q_[k];
    return 0.5 * e;
}

}  // namespace ameoto
