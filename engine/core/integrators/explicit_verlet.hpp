// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The CORDIS-ANIMA explicit scheme (position Verlet), with sub-steps.
//
// Interface (all integrators share this shape; TransverseNetwork dispatches on Integrator):
//   ExplicitVerlet s;
//   s.init(arrays, output_step_s, sub_steps);     // allocates state
//   double f = s.step(arrays, ext);               // one output step; returns the net force (below)
//   s.reset(); s.finite(); s.position(i); s.velocity(i); s.energy(arrays);
//
// Scheme (seed section 4.1): x[n+1] = 2 x[n] - x[n-1] + T'^2 F/m with F = ext - K x[n] - C v[n], the
// velocity by backward difference v[n] = (x[n] - x[n-1]) / T', T' = T / sub_steps; ext is held over the
// sub-steps. Stable iff omega^2 T'^2 + 2 gamma T' < 4 (Jury test on
// z^2 - (2 - w^2 T'^2 - g T') z + (1 - g T'), gamma = z/m); undamped frequency (2/T') asin(omega0 T'/2)
// (physics.md section 3).
// Net force: sum over masses of F, averaged over the sub-steps: sum_i m_i (v_i[n+1] - v_i[n]) / T, the
// change of momentum over the output step over T (internal links cancel), as every integrator returns.

#include <vector>

#include "engine/core/integrators/network_arrays.hpp"

namespace ameoto {

class ExplicitVerlet {
public:
    void init(const NetworkArrays& net, double output_step_s, int sub_steps);
    double step(const NetworkArrays& net, const double* ext);
    void reset();
    bool finite() const;
    double position(std::size_t i) const { return x_[i]; }
    double velocity(std::size_t i) const { return (x_[i] - previous_[i]) * inverse_dt_; }
    double energy(const NetworkArrays& net) const;   // with the backward-difference velocity
    double sub_step_s() const { return dt_; }

private:
    double sub_step(const NetworkArrays& net, const double* ext);
    std::vector<double> x_, previous_, force_, velocity_;
    mutable std::vector<double> scratch_;
    double dt_ = 0.0, inverse_dt_ = 0.0;
    int sub_steps_ = 1;
};

}  // namespace ameoto
