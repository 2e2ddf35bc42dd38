#pragma once
// A CORDIS-ANIMA mass-interaction network whose masses move along one axis (transverse
// displacement u of a membrane), stored as structure-of-arrays.
//
// Interface:
//   TransverseNetwork net;                                  // build phase (allocates)
//   int m = net.add_mass(mass_kg, ground_damping_N_s_per_m);
//   net.add_link(a, b, stiffness_N_per_m, damping_N_s_per_m);   // spring-damper between masses
//   net.add_anchor(a, stiffness, damping);                  // link to a fixed point (u = 0)
//   net.finalize(time_step_s);                              // stability check, sub-steps; allocates
//   ---- render phase: never allocates ----
//   net.apply_force(m, newtons);                            // external force for the next step
//   double f = net.step();                                  // one output sample; returns the sum of
//                                                           // forces on all masses (see below)
//   net.stability()                                         // omega_max bound, sub-steps chosen
//   net.reset();                                            // all masses to rest
//
// Scheme: the CORDIS explicit scheme (position Verlet), x[n+1] = 2x[n] - x[n-1] + T^2 F/m, with
// velocities by backward difference v = (x[n] - x[n-1]) / T, as in CORDIS-ANIMA and the seed
// (section 4.1). Link force F1 = -F2 = -k (x1 - x2) - z (v1 - v2) (rest length is zero for transverse
// displacement: the membrane's tension lives in k, see models/membrane.hpp).
//
// Stability (../shared/reference/physics.md section 3): an undamped oscillator is stable iff
// omega T < 2; with the backward-difference damping gamma = z/m the exact condition is
// omega^2 T^2 < 4 - 2 gamma T (Jury test on z^2 - (2 - w^2T^2 - gT) z + (1 - gT)). omega_max^2 and
// gamma_max are bounded by Gershgorin: (anchor + 2 * sum of link stiffnesses at a mass) / m (exact for a
// single anchored mass; anchors and ground dampers sit on the diagonal only). finalize() picks the
// fewest sub-steps that keep omega_max^2 T'^2 + 2 gamma_max T' under 90 % of 4, so a body never runs
// past its bound; step() also reports non-finite state so the owner can reset it.

#include <cstdint>
#include <vector>

namespace ameoto {

struct StabilityReport {
    double omega_max_bound = 0.0;   // rad/s, Gershgorin upper bound
    double gamma_max_bound = 0.0;   // 1/s, damping rate bound
    double time_step = 0.0;         // s, the caller's output step
    int sub_steps = 1;              // internal steps per output step
    double margin() const;          // (omega^2 T'^2 + 2 gamma T') / 4 at the chosen sub-step; < 1 is stable
};

class TransverseNetwork {
public:
    int add_mass(double mass_kg, double ground_damping);
    void add_link(int a, int b, double stiffness, double damping);
    void add_anchor(int a, double stiffness, double damping);

    // Computes the stability bound and sub-steps for the output step T (s). Allocates.
    void finalize(double time_step_s);

    void apply_force(int mass, double newtons) { external_[static_cast<std::size_t>(mass)] += newtons; }

    // Advances one output step (all sub-steps). Returns the sum over masses of the total force acting
    // on each mass (links cancel in pairs, so this is external force minus anchor reactions and
    // ground damping): by Newton's third law the membrane's net volume acceleration, which the
    // far-field pressure is built from. External forces are held over the sub-steps, then cleared.
    double step();

    void reset();
    bool finite() const;   // false once any position is NaN or Inf

    int mass_count() const { return static_cast<int>(position_.size()); }
    int link_count() const { return static_cast<int>(link_a_.size()); }
    double position(int m) const { return position_[static_cast<std::size_t>(m)]; }
    double velocity(int m) const;                 // backward difference over the last sub-step
    double mass(int m) const { return 1.0 / inverse_mass_[static_cast<std::size_t>(m)]; }
    double kinetic_plus_potential_energy() const; // J, for tests and the runaway guard
    const StabilityReport& stability() const { return stability_; }

private:
    double sub_step(double dt);

    // masses (structure of arrays)
    std::vector<double> position_, previous_, inverse_mass_, ground_damping_, anchor_stiffness_,
        force_, velocity_, external_;
    // links
    std::vector<std::int32_t> link_a_, link_b_;
    std::vector<double> link_stiffness_, link_damping_;
    StabilityReport stability_;
    double sub_dt_ = 0.0;
};

}  // namespace ameoto
