// SPDX-License-Identifier: GPL-3.0-or-later
// The lattice drop on a rigid plane (engine/models/wet_impact.hpp, measure_rigid_impact): the force
// pulse against Gordillo et al. (2018) and where the impact's energy goes, for docs/impacts.md.
//
//   build/tests/rigid_impact_bench [--impact wet|seed] [--restitution E] [--rate HZ] [--trace D_MM]
// prints, per diameter (1, 2, 4 mm and the others of the table) at its terminal speed: masses,
// impulse / (m V), peak / (0.8 rho V^2 D^2), peak time / (D / V), the 5-95 % impulse span / (D / V),
// pieces, and the energy table as fractions of the initial kinetic energy (over 20 ms). --trace prints
// the per-sample force of one size (time in units of D / V, force in units of 0.8 rho V^2 D^2).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "engine/models/wet_impact.hpp"

int main(int argc, char** argv) {
    ameoto::ImpactModel model = ameoto::ImpactModel::wet;
    double rate = 48000.0, trace = 0.0, restitution = 1.0;   // e: the seed exchange's
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--impact" && i + 1 < argc) {
            const auto m = ameoto::find_impact_model(argv[++i]);
            if (!m) { std::fprintf(stderr, "--impact: wet or seed\n"); return 2; }
            model = *m;
        } else if (a == "--restitution" && i + 1 < argc) {
            restitution = std::atof(argv[++i]);
        } else if (a == "--rate" && i + 1 < argc) {
            rate = std::atof(argv[++i]);
        } else if (a == "--trace" && i + 1 < argc) {
            trace = std::atof(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: rigid_impact_bench [--impact wet|seed] [--restitution E] [--rate HZ] [--trace D_MM]\n");
            return 2;
        }
    }
    const double rho = ameoto::liquids::water().density;
    auto spec_for = [&](double d_mm, double seconds) {
        ameoto::RigidImpactSpec s;
        s.diameter_m = d_mm * 1e-3;
        s.sample_rate = rate;
        s.law.model = model;
        s.law.restitution = restitution;
        s.seconds = seconds;
        return s;
    };
    if (trace > 0.0) {
        const ameoto::RigidImpact r = ameoto::measure_rigid_impact(spec_for(trace, 0.0));
        const double f0 = r.gordillo_peak(rho), T = 1.0 / rate;
        for (std::size_t n = 0; n < r.force.size(); ++n)
            std::printf("%.4f %.4f\n", ((static_cast<double>(n) - r.first_contact) + 0.5) * T / r.tau(), r.force[n] / f0);
        return 0;
    }
    std::printf("impact %s (e %.2f for seed) at %.0f Hz\n", ameoto::impact_model_name(model), restitution, rate);
    std::printf("%5s %5s %6s %6s %8s %8s %8s %8s %6s |%7s %7s %7s %7s %7s %7s %7s %7s %8s\n", "D_mm", "V", "masses",
                "J/mV", "F/0.8", "t_pk/tau", "len/tau", "J_ms", "pieces", "kin", "flying", "elastic", "collis", "viscous",
                "drag", "broken", "gravity", "residual");
    for (const double d_mm : {1.0, 2.0, 3.0, 4.0, 5.0}) {
        const ameoto::RigidImpact r = ameoto::measure_rigid_impact(spec_for(d_mm, 0.02));
        const ameoto::ImpactEnergy& e = r.energy;
        const double k0 = e.initial_kinetic;
        std::printf("%5.1f %5.2f %6d %6.3f %8.3f %8.3f %8.3f %8.2e %6d |%7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %8.4f\n",
                    d_mm, r.speed_m_per_s, r.masses, r.impulse_n_s / r.momentum(), r.peak_n / r.gordillo_peak(rho),
                    r.peak_time_s / r.tau(), r.length_s / r.tau(), r.impulse_n_s, r.pieces, e.kinetic / k0,
                    e.kinetic_flying / k0, e.elastic / k0, e.collision / k0, e.viscous / k0, e.drag / k0, e.broken / k0,
                    e.gravity_work / k0, e.residual() / k0);
    }
    return 0;
}
