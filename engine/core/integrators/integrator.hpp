// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The time integrators a transverse network can run, chosen per body.
//
// Interface:
//   Integrator::explicit_verlet    // CORDIS / position Verlet (default; what the canopy runs)
//   Integrator::symplectic_euler   // v += T M^-1 F(x, v); x += T v
//   Integrator::trapezoidal        // Newmark average acceleration (beta = 1/4, gamma = 1/2)
//   Integrator::backward_euler     // implicit Euler
//   Integrator::modal              // exact per-mode two-pole resonators (linear, proportional damping)
//   integrator_name(Integrator)    // "explicit Verlet", ... for messages
//   conditionally_stable(Integrator)   // true for the explicit schemes (omega T < 2 family)
//
// Stability and warping of each (../../shared/reference/physics.md section 3; docs/integrators.md,
// "Integrators and stability"):
//   explicit Verlet, symplectic Euler: stable iff omega^2 T^2 + 2 gamma T < 4 (gamma = z/m), frequency
//     (2/T) asin(omega0 T / 2);
//   trapezoidal: unconditionally stable, energy-conserving for linear links, (2/T) atan(omega0 T / 2);
//   backward Euler: unconditionally stable, numerical damping growing with omega T;
//   modal: exact at any T (the continuous modes sampled).

namespace ameoto {

enum class Integrator { explicit_verlet, symplectic_euler, trapezoidal, backward_euler, modal };

constexpr const char* integrator_name(Integrator i) {
    switch (i) {
        case Integrator::explicit_verlet: return "explicit Verlet";
        case Integrator::symplectic_euler: return "symplectic Euler";
        case Integrator::trapezoidal: return "trapezoidal";
        case Integrator::backward_euler: return "backward Euler";
        case Integrator::modal: return "modal";
    }
    return "?";
}

constexpr bool conditionally_stable(Integrator i) {
    return i == Integrator::explicit_verlet || i == Integrator::symplectic_euler;
}

}  // namespace ameoto
