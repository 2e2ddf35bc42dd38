// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The canopy in air as modal resonators: the whole canopy's modes with the air's added mass on both
// faces (air_loading.hpp: K phi = w^2 (M + M_a) phi), each run exactly as a two-pole resonator, the
// drops' contact forces projected onto them through the mode shapes and the struck node's motion read
// back through them. What Canopy runs in place of its lattice once it is given air (Canopy::set_air).
//
// Interface:
//   AirCanopyOptions o;                                  // air, sampling of the added mass, cutoff
//   std::shared_ptr<const AirCanopyModes> m = build_air_canopy_modes(canopy, time_step_s, o);
//                                                        // build phase: allocates, ~0.45 s for the
//                                                        // default canopy; throws std::invalid_argument
//                                                        // (bad options, a curved canopy's plan is used)
//   AirCanopyState s; s.init(*m);                        // allocates the state (build phase)
//   ---- audio-safe from here: no allocation, no locks ----
//   s.apply_force(m, node, newtons);                     // for the next step (node: panel * nodes + i)
//   s.step(m);                                           // one sample
//   s.displacement(m, node), s.velocity(m, node)         // u, du/dt along the node's normal
//   s.accelerations()                                    // each mode's mean q'' over the last step
//   s.modal_q(), s.modal_qd()                            // each mode's q, q' after the last step
//   s.displacement_bound(m), s.velocity_bound(m)         // >= |u|, >= |du/dt| at every node, O(modes)
//   s.forced_nodes(), s.forced_node(j), s.forced_newtons(j)   // the forces the last step took, summed per
//                                                        // node (the compressible push: air_push.hpp)
//   s.finite(), s.reset(), s.energy()
//
// Modes (air_loading.hpp): Phi' (M + M_a) Phi = I, u = Phi q, and each mode obeys
//   q_k'' + 2 s_k q_k' + w_k^2 q_k = phi_k' f,
// s_k = the material's (Phi' C Phi)_kk / 2 (classical damping) plus, with radiation on, the mode's
// radiation damping (air_loading.hpp, radiation_damping). The step is the modal integrator's
// (core/integrators/modal.hpp: the kick q' += T p, then the exact transition over T): exact for any T.
// Compressible poles: the modes with every panel alike (the canopy's Fourier block m = 0) move the most
// air, out to the canopy's size, where the incompressible M_a misses the air's compressibility; those up
// to compressible_in_phase_ka take that block's analytic poles with M_a(omega) (air_loading_in_phase.hpp):
// the lowest 84.6 -> 81.2 Hz at 6.8 /s, the next 168.7 -> 163.2 Hz at 7.8 /s, each decay the material's and
// the compressible air's radiation together. Their shapes are the block's real eigenvectors with the
// air's extra mass at the pole, scaled to the pole's residue, and their air forces carry that extra mass
// (M_a(0) + Re(M_a(w_k) - M_a(0))) phi_k: the extra mass couples the block's modes (the second takes 0.115
// of the first's shape), which a listener on the axis hears between them. Every other mode keeps its
// incompressible pole, shape and force, and so Phi' (M + M_a) Phi = I holds but for those two. Why ka = 2
// (docs/canopy-air.md, "The compressible poles of the in-phase modes"): the band levels' RMS error against
// the finest reference, through the band filters, was 1.16 dB with no pole moved, 0.93 with the lowest,
// 0.89 with the two (ka 2), 0.92 with the four under ka 3 (245 Hz -0.5 %, 259 Hz -2.6 %), all with the
// incompressible shapes; with the two's shapes 0.80. The build costs about 0.15 s more (the block's
// 300-cell complex solve, twice a mode).
// Cutoff: modes above max_frequency_hz are dropped (they neither move nor radiate). The default keeps
// every mode the lattice has (the 400-node default canopy's: 81.2 to 962.6 Hz in air): the lattice
// itself is the resolution limit, and a panel's modes above about 700 Hz already have wavelengths under
// four lattice spacings (docs/canopy-air.md, "In air").
// Contact: a collision needs the node's mass as an impact sees it (membrane_collision.cpp): in air the
// node's instantaneous (impulse) mobility is Delta v_i / J = sum_k phi_ik^2 = ((M + M_a)^-1)_ii over the
// kept modes, so the node's contact mass is 1 / sum_k phi_ik^2: heavier than its structural mass, as
// the air next to it moves with it.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/lane_sums.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading.hpp"

namespace ameoto {

class Canopy;
struct AirKernels;

struct AirCanopyOptions {
    double air_density = constants::air_density;            // rho0, kg/m^3
    double speed_of_sound = constants::speed_of_sound_air;   // c, m/s
    CanopyAirMassOptions air_mass{};    // the added mass's sampling: per-panel sub-cells, extrapolated to
                                        // zero cell size (air_loading.hpp; +0.2 % of Lamb's for the rigid canopy)
    double max_frequency_hz = 20000.0;  // modes above are dropped
    bool radiation_damping = true;      // add each mode's radiation damping to its decay
    double compressible_in_phase_ka = 2.0;   // the in-phase modes up to this k a (a the canopy's radius:
                                             // 218 Hz on the default) take their compressible poles; 0: none
    bool operator==(const AirCanopyOptions&) const = default;
};

struct AirCanopyModes {
    int nodes = 0;                  // panel-major, panel * nodes_per_panel + node
    int modes = 0;                  // kept
    int modes_found = 0;            // before the cutoff
    double time_step_s = 0.0;
    double cutoff_hz = 0.0;         // max_frequency_hz as given
    Eigen::VectorXd omega;          // rad/s
    Eigen::VectorXd rate;           // 1/s: the material's and the radiation's
    Eigen::VectorXd radiation_rate; // 1/s: the radiation's part (0 when off)
    std::vector<double> shape;      // node-major: shape[node * modes + k] = phi_k at the node
    std::vector<double> t11, t12, t21, t22;   // each mode's transition over T
    std::vector<double> contact_mass;         // kg per node: 1 / sum_k phi_ik^2
    std::vector<double> largest_shape;        // per mode: max over nodes of |phi_ik| (a bound on |u|)
    Eigen::MatrixXd air_force;      // [node, mode]: (M_a phi_k)_i, N on the air per unit q_k''
    // [node i, node e]: the force on the air at i, N, when a newton acts at e, at once (before the modes
    // move): M_a (M + M_a)^-1 = sum_k (M_a phi_k) phi_k' over the kept modes (the instantaneous push,
    // dipole_radiation.hpp). Its column for a node of the default canopy's panel centroid holds 38 % of
    // the newton on the node and 92 % in all (the rest moves the fabric).
    Eigen::MatrixXd instantaneous_push;
    std::vector<double> node_area;  // m^2 per node (the added mass's cells)
};

std::shared_ptr<const AirCanopyModes> build_air_canopy_modes(const Canopy& canopy, double time_step_s,
                                                             const AirCanopyOptions& options = AirCanopyOptions{});

class AirCanopyState {
public:
    void init(const AirCanopyModes& modes);
    // Gathered per node and projected onto the modes once per forced node in step(): a lattice drop's
    // breakup puts tens of contacts a sample on a few nodes, and a projection costs a sum over the modes
    // (it was a sixth of a breakup block's CPU when each contact projected its own force).
    void apply_force(const AirCanopyModes&, int node, double newtons) {
        const auto i = static_cast<std::size_t>(node);
        if (forced_stamp_[i] != steps_) {   // a node's first force this step: listed once (at most every node)
            forced_stamp_[i] = steps_;
            pending_.node[static_cast<std::size_t>(pending_.count++)] = node;
        }
        pending_.newtons[i] += newtons;
    }
    void step(const AirCanopyModes& m);
    // A node's reading costs a sum over the modes; the collisions read the same nodes many times a step
    // (every mass of a lattice drop near the membrane: a 5 mm drop's breakup makes about 30 contacts a
    // sample on a few nodes), so each is kept until the next step or reset. (One thread owns a state: the
    // audio thread, or the build thread before it.)
    double displacement(const AirCanopyModes& m, int node) const { return cached(m, node, q_, u_, u_stamp_); }
    double velocity(const AirCanopyModes& m, int node) const { return cached(m, node, qd_, v_, v_stamp_); }
    const double* accelerations() const { return a_.data(); }   // per mode, m/s^2 per unit of q
    const double* modal_q() const { return q_.data(); }          // per mode, q after the last step
    const double* modal_qd() const { return qd_.data(); }        // per mode, q' after the last step
    // sum_k max_i |phi_ik| |q_k| >= |u_i| at every node: the collision broad phase's bound, O(modes)
    // where the exact extremes would cost O(nodes x modes).
    double displacement_bound(const AirCanopyModes& m) const { return bound(m, q_, bounds_[0], bound_stamp_[0]); }
    // sum_k max_i |phi_ik| |q_k'| >= |du_i/dt| at every node, likewise: the drop's coarse-step floor
    // (drop_on_canopy_collide.cpp) needs only a bound on the fastest node.
    double velocity_bound(const AirCanopyModes& m) const { return bound(m, qd_, bounds_[1], bound_stamp_[1]); }
    int forced_nodes() const { return taken_.count; }
    int forced_node(int j) const { return taken_.node[static_cast<std::size_t>(j)]; }
    double forced_newtons(int j) const { return taken_.newtons[static_cast<std::size_t>(taken_.node[static_cast<std::size_t>(j)])]; }
    bool finite() const;
    void reset();
    double energy() const;   // J: 1/2 sum (q'^2 + w^2 q^2), the membrane's and the air's near field

private:
    double cached(const AirCanopyModes& m, int node, const std::vector<double>& x, std::vector<double>& value,
                  std::vector<std::uint64_t>& stamp) const {
        const auto i = static_cast<std::size_t>(node);
        if (stamp[i] != steps_) {
            value[i] = lane_sums::dot(m.shape.data() + i * static_cast<std::size_t>(m.modes), x.data(), x.size());
            stamp[i] = steps_;
        }
        return value[i];
    }
    double bound(const AirCanopyModes& m, const std::vector<double>& x, double& value, std::uint64_t& stamp) const {
        if (stamp != steps_) {
            value = lane_sums::abs_dot(m.largest_shape.data(), x.data(), x.size());
            stamp = steps_;
        }
        return value;
    }
    std::vector<double> q_, qd_, p_, a_, omega2_;
    const AirKernels* kernels_ = nullptr;   // air_canopy_kernels.hpp, chosen by init()
    // The readings of this step (steps_ counts steps and resets from 1; a stamp of 0 is never current).
    std::uint64_t steps_ = 1;
    mutable std::vector<double> u_, v_;
    mutable std::vector<std::uint64_t> u_stamp_, v_stamp_;
    // The forces of the step being gathered and of the step taken: the nodes listed in order, each
    // node's sum (sized to the nodes by init: no list can overflow). step() swaps them.
    struct Forces {
        std::vector<int> node;
        std::vector<double> newtons;   // per node
        int count = 0;
        void clear() {
            for (int j = 0; j < count; ++j) newtons[static_cast<std::size_t>(node[static_cast<std::size_t>(j)])] = 0.0;
            count = 0;
        }
    };
    Forces pending_, taken_;
    std::vector<std::uint64_t> forced_stamp_;
    mutable double bounds_[2] = {0.0, 0.0};
    mutable std::uint64_t bound_stamp_[2] = {0, 0};
};

}  // namespace ameoto
