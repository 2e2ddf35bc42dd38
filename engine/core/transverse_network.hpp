// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A CORDIS-ANIMA mass-interaction network whose masses move along one axis (transverse displacement
// u of a membrane), stored as structure-of-arrays, advanced by the integrator chosen for this body.
//
// Interface:
//   TransverseNetwork net;                                  // build phase (allocates)
//   int m = net.add_mass(mass_kg, ground_damping_N_s_per_m);
//   net.add_link(a, b, stiffness_N_per_m, damping_N_s_per_m);   // spring-damper between masses
//   net.add_anchor(a, stiffness, damping);                  // link to a fixed point (u = 0)
//   net.finalize(time_step_s);                              // explicit Verlet, sub-steps if needed
//   net.finalize(time_step_s, NetworkOptions{...});         // integrator, stability policy, modal
//                                                           // selection, runtime guard; allocates;
//                                                           // throws StabilityError when refused
//   net.stability()                                         // the bounds and what was decided (message)
//   ---- render phase: never allocates ----
//   net.apply_force(m, newtons);                            // external force for the next step
//   double f = net.step();                                  // one output sample; returns the net force
//   net.guard();                                            // runtime guard: reset if non-finite or
//                                                           // runaway; true if it reset (counted)
//   net.reset();                                            // all masses to rest
//   net.position(m), net.velocity(m), net.kinetic_plus_potential_energy(), net.finite()
//   net.positions(out), net.velocities(out)                 // every mass at once (out: mass_count())
//   net.guard_resets(), net.guard_options()                 // the runtime guard's count and settings
//
// Integrators (integrators/*.hpp, docs/integrators.md "Integrators and stability"): explicit Verlet (the
// CORDIS scheme, default), symplectic Euler, trapezoidal (Newmark average acceleration), backward Euler,
// modal. Link force F1 = -F2 = -k (x1 - x2) - z (v1 - v2) (rest length zero for transverse
// displacement: the membrane's tension lives in k, see models/membrane.hpp).
// Net force: step() returns the change of the body's momentum over the step divided by T, i.e. the sum
// over masses of the force acting on each, averaged over the step: links cancel in pairs, so it is the
// external force minus the anchors' reactions and the ground damping; by Newton's third law the
// membrane's net volume acceleration, which the far-field pressure is built from.
// Stability (stability.hpp): finalize() bounds omega_max by Gershgorin and by power iteration, and for
// the explicit schemes applies the caller's policy (sub-steps, switch to trapezoidal, refuse, none).
// The runtime guard (stability.hpp, RuntimeGuard) resets a body whose state went non-finite or whose
// energy ran away and counts it; the owner calls guard() (the canopy does, once per block) or sets
// GuardOptions::check_every_steps.

#include <cstdint>
#include <vector>

#include "engine/core/integrators/backward_euler.hpp"
#include "engine/core/integrators/explicit_verlet.hpp"
#include "engine/core/integrators/integrator.hpp"
#include "engine/core/integrators/modal.hpp"
#include "engine/core/integrators/network_arrays.hpp"
#include "engine/core/integrators/symplectic_euler.hpp"
#include "engine/core/integrators/trapezoidal.hpp"
#include "engine/core/stability.hpp"

namespace ameoto {

struct NetworkOptions {
    Integrator integrator = Integrator::explicit_verlet;
    StabilityOptions stability{};
    ModalOptions modal{};
    GuardOptions guard{};
    bool operator==(const NetworkOptions&) const = default;
};

class TransverseNetwork {
public:
    int add_mass(double mass_kg, double ground_damping);
    void add_link(int a, int b, double stiffness, double damping);
    void add_anchor(int a, double stiffness, double damping);

    void finalize(double time_step_s) { finalize(time_step_s, NetworkOptions{}); }
    void finalize(double time_step_s, const NetworkOptions& options);

    void apply_force(int mass, double newtons) { external_[static_cast<std::size_t>(mass)] += newtons; }

    // Advances one output step (all sub-steps); external forces are held over it, then cleared.
    double step();

    bool guard();
    void reset();
    bool finite() const;   // false once any state variable is NaN or Inf

    int mass_count() const { return static_cast<int>(arrays_.mass_count()); }
    int link_count() const { return static_cast<int>(arrays_.link_count()); }
    double position(int m) const;
    double velocity(int m) const;   // explicit Verlet: backward difference over the last sub-step
    // Every mass's position / velocity into out[0 .. mass_count()), the same values as position(m) and
    // velocity(m), with one dispatch for the whole body instead of one per call (the far field and the
    // collision broad phase read every node every sample).
    void positions(double* out) const;
    void velocities(double* out) const;
    double mass(int m) const { return arrays_.mass(static_cast<std::size_t>(m)); }
    double kinetic_plus_potential_energy() const;   // J; modal: of the kept modes
    const StabilityReport& stability() const { return stability_; }
    Integrator integrator() const { return stability_.integrator; }
    std::uint64_t guard_resets() const { return guard_.resets(); }
    double guard_energy_limit() const { return guard_.energy_limit(); }
    const GuardOptions& guard_options() const { return guard_.options(); }
    const NetworkArrays& arrays() const { return arrays_; }
    const Modal& modal() const { return modal_; }   // modes kept, resonators (modal only)

private:
    NetworkArrays arrays_;
    std::vector<double> external_;
    StabilityReport stability_;
    RuntimeGuard guard_;
    int check_every_ = 0, since_check_ = 0;
    double time_step_ = 0.0;
    ExplicitVerlet explicit_;
    SymplecticEuler symplectic_;
    Trapezoidal trapezoidal_;
    BackwardEuler backward_;
    Modal modal_;
};

}  // namespace ameoto
