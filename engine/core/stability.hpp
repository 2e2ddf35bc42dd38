// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Where methods fail: a body's stability bound before it runs, the policy when the chosen integrator
// cannot run at the caller's step, and the runtime guard that catches what slips through.
//
// Interface:
//   double w = gershgorin_omega_max(arrays);          // rad/s, cheap upper bound on omega_max
//   double e = power_iteration_omega_max(arrays);     // rad/s, tight estimate (from below)
//   double g = gershgorin_gamma_max(arrays);          // 1/s, bound on the damping rate z/m
//   StabilityReport r = assess_stability(arrays, T, Integrator::explicit_verlet, StabilityOptions{});
//   r.refused, r.message, r.sub_steps, r.integrator   // what will run, and why
//   RuntimeGuard guard; guard.configure(GuardOptions{}, T);
//   guard.inject(sqrt_joules); guard.exceeded(finite, energy); guard.count_reset();
//
// Bounds (physics.md section 3): the explicit schemes are stable iff omega_max^2 T^2 + 2 gamma T < 4
// (explicit_verlet.hpp; undamped: omega_max T < 2), omega_max^2 the largest eigenvalue of M^-1 K.
// Gershgorin: every eigenvalue of M^-1 K lies within max_i (anchor_i + 2 sum of i's links) / m_i (row i's
// diagonal plus its off-diagonal magnitudes), likewise gamma for M^-1 C. Power iteration on the
// symmetric M^-1/2 K M^-1/2 (same eigenvalues) converges to omega_max^2 from below (its Rayleigh
// quotient never exceeds lambda_max), so the Gershgorin bound is the safe one and the default; the
// tight estimate saves sub-steps (Gershgorin's omega^2 is 4/3 too high in a triangular lattice, whose Laplacian
// tops out at 9 k/m against the bound's 12 k/m) when the caller chooses it.
// A scheme runs when its margin (omega^2 T'^2 + 2 gamma T') / 4 is below `safety` (0.9: 10 % head-room
// for rounding and a slightly low estimate). Otherwise the policy decides:
//   sub_step:          the fewest sub-steps that bring the margin below safety (refused beyond max);
//   switch_to_stable:  run the trapezoidal rule instead (unconditionally stable);
//   refuse:            refuse, with a message naming the bound: "omega_max T = 41.2 exceeds 2 for the
//                      explicit Verlet scheme; use sub-steps or an implicit method";
//   none:              run as asked (for demonstrations and tests: only the runtime guard protects).
// min_sub_steps > 1 oversamples an explicit scheme for accuracy (its frequency warping falls as
// (omega T / n)^2, integrators/integrator.hpp): the report runs max(min_sub_steps, what stability needs).
// Implicit schemes and modal never need any of this; their report still carries the bounds.
// Runtime guard: a body whose state is non-finite or whose energy exceeds a limit is reset and counted.
// The limit is the caller's (energy_limit_J > 0) or energy_factor times the square of the injected
// amplitude A = sum over steps of sqrt(e_n), e_n = 1/2 sum_i (T f_i)^2 / m_i the kinetic energy the
// step's impulse would give the body at rest. For a passive linear body sqrt(E) is a norm of the state
// that the free evolution never increases, and impulses add states, so sqrt(E(t)) <= A (triangle
// inequality): E > 1e6 A^2 cannot happen without a numerical instability (the discrete schemes' energies
// differ from the continuous one by factors of order 1 + omega T, far inside 1e6). So it never fires on a
// stable body, however long and however driven. Over a long rain A grows with the impacts and the limit
// with it, which only delays the catch of an exponential runaway by a few steps (the non-finite check
// remains); memory_s > 0 makes A forget with that time constant instead (then an undamped body left
// ringing for ~7 memory_s could trip it).

#include <stdexcept>
#include <string>

#include "engine/core/integrators/integrator.hpp"
#include "engine/core/integrators/network_arrays.hpp"

namespace ameoto {

enum class StabilityPolicy { sub_step, switch_to_stable, refuse, none };
enum class StabilityBound { gershgorin, power_iteration };

struct StabilityOptions {
    StabilityPolicy policy = StabilityPolicy::sub_step;
    StabilityBound bound = StabilityBound::gershgorin;
    int max_sub_steps = 4096;
    double safety = 0.9;   // largest margin allowed to run
    int min_sub_steps = 1; // explicit schemes: at least this many (accuracy: method_choice.hpp), 1..max
    bool operator==(const StabilityOptions&) const = default;
};

struct StabilityReport {
    double omega_max_bound = 0.0;      // rad/s, Gershgorin upper bound
    double omega_max_estimate = 0.0;   // rad/s, power iteration
    double gamma_max_bound = 0.0;      // 1/s, Gershgorin bound on M^-1 C
    double time_step = 0.0;            // s, the caller's output step
    int sub_steps = 1;                 // internal steps per output step
    Integrator requested = Integrator::explicit_verlet;
    Integrator integrator = Integrator::explicit_verlet;   // what runs (after switch_to_stable)
    StabilityPolicy policy = StabilityPolicy::sub_step;
    StabilityBound bound = StabilityBound::gershgorin;
    bool refused = false;
    std::string message;               // what was decided and why, with the numbers

    double omega_max() const;          // the bound that decided (bound)
    // (omega_max^2 T'^2 + 2 gamma T') / 4 at the chosen sub-step: < 1 is stable for the explicit schemes.
    double margin() const;
};

class StabilityError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

double gershgorin_omega_max(const NetworkArrays& arrays);
double gershgorin_gamma_max(const NetworkArrays& arrays);
double power_iteration_omega_max(const NetworkArrays& arrays, int max_iterations = 20000, double tolerance = 1e-13);
double explicit_margin(double omega, double gamma, double dt);

// Never throws: a refusal is reported (refused, message); TransverseNetwork::finalize throws it.
StabilityReport assess_stability(const NetworkArrays& arrays, double time_step_s, Integrator integrator,
                                 const StabilityOptions& options);

struct GuardOptions {
    bool enabled = true;
    double energy_factor = 1e6;    // limit = factor * (injected amplitude)^2 ...
    double energy_limit_J = 0.0;   // ... unless this is > 0
    double memory_s = 0.0;         // > 0: forgetting time of the injected amplitude; 0: never forget
    int check_every_steps = 0;     // > 0: step() checks itself this often; 0: the owner calls guard()
    bool operator==(const GuardOptions&) const = default;
};

class RuntimeGuard {
public:
    void configure(const GuardOptions& options, double time_step_s);
    void inject(double sqrt_joules) { amplitude_ = amplitude_ * forget_ + sqrt_joules; }
    double energy_limit() const;
    bool exceeded(bool finite, double energy) const;   // true: reset the body
    void clear() { amplitude_ = 0.0; }
    void count_reset() { ++resets_; }
    unsigned long long resets() const { return resets_; }
    const GuardOptions& options() const { return options_; }

private:
    GuardOptions options_;
    double forget_ = 1.0, amplitude_ = 0.0;
    unsigned long long resets_ = 0;
};

}  // namespace ameoto
