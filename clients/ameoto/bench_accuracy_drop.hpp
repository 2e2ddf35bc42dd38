// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The free drop's rows of `ameoto bench accuracy`: a 3 mm water drop (engine/models/drop.hpp: a 3-D
// lattice calibrated so that it oscillates at Rayleigh's n = 2 frequency, 66 Hz), no gravity, no drag,
// stretched 1 % along z and let go, run by the schemes a Body3D offers (explicit Verlet, symplectic
// Euler) at 1x, 2x, 4x, 8x the sub-steps its stiffness needs.
//
// Interface:
//   DropAccuracy d = measure_drop(Integrator::symplectic_euler, 2, reference_hz, seconds, runs);
//   double hz = drop_frequency(Integrator::symplectic_euler, 64);   // the converged reference
//   d.ns_per_sample, d.cents, d.sub_steps, d.rayleigh_hz
//
// Error: the frequency of its n = 2 oscillation (the elongation, sum m (z^2 - (x^2 + y^2) / 2) about the
// centre of mass, from zero crossings over 0.25 s) against a converged run at 64 times the needed
// sub-steps, in cents. (Against Rayleigh's formula itself the lattice's calibration error would add a
// constant: the lattice oscillates at its own n = 2 mode, calibrated to Rayleigh's frequency at
// infinitesimal amplitude.) No spectral distance: a free drop alone makes no sound in this model.
// Cost: ns per output sample of the drop's step (thread CPU time, median of runs).

#include "engine/core/integrators/integrator.hpp"

namespace ameoto::client {

struct DropAccuracy {
    int sub_steps = 1;           // what ran (the factor times what stability needs)
    double ns_per_sample = 0.0;
    double hz = 0.0, cents = 0.0;
    double rayleigh_hz = 0.0;
};

double drop_frequency(Integrator integrator, int factor, int* sub_steps = nullptr, double* rayleigh_hz = nullptr);
DropAccuracy measure_drop(Integrator integrator, int factor, double reference_hz, double seconds, int runs);

}  // namespace ameoto::client
