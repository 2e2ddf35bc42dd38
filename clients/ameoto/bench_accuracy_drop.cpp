// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_accuracy_drop.hpp"

#include <cmath>
#include <vector>

#include "clients/ameoto/bench_accuracy_errors.hpp"
#include "clients/ameoto/bench_timer.hpp"
#include "engine/models/drop.hpp"
#include "engine/models/liquid.hpp"

namespace ameoto::client {

namespace {

constexpr double diameter = 3e-3;

double elongation(const Body3D& body) {
    const Vec3 c = body.centre_of_mass();
    double q = 0.0;
    for (int i = 0; i < body.mass_count(); ++i) {
        const Vec3 p = body.position(i) - c;
        q += body.mass(i) * (p.z * p.z - 0.5 * (p.x * p.x + p.y * p.y));
    }
    return q;
}

// The drop, stretched 1 % (volume kept) about its centre of mass, finalized at factor x the sub-steps
// stability needs. Returns its elongation at rest through `rest`.
Drop stretched_drop(Integrator integrator, int factor, double& rest) {
    Drop drop = make_drop(diameter, liquids::water(), Vec3{}, Vec3{}, DragPreset::none);
    Body3D& body = drop.body;
    body.set_gravity(Vec3{});
    body.set_integrator(integrator);
    rest = elongation(body);
    const Vec3 c = body.centre_of_mass();
    const double sz = 1.01, sx = 1.0 / std::sqrt(sz);
    for (int i = 0; i < body.mass_count(); ++i) {
        const Vec3 p = body.position(i) - c;
        body.set_position(i, c + Vec3{sx * p.x, sx * p.y, sz * p.z});
    }
    const int needed = body.finalize(1.0 / bench_sample_rate).sub_steps;
    body.finalize(1.0 / bench_sample_rate, needed * factor);
    return drop;
}

}  // namespace

double drop_frequency(Integrator integrator, int factor, int* sub_steps, double* rayleigh_hz) {
    double rest = 0.0;
    Drop drop = stretched_drop(integrator, factor, rest);
    if (sub_steps) *sub_steps = drop.body.stability().sub_steps;
    if (rayleigh_hz) *rayleigh_hz = drop.calibration.rayleigh_hz;
    std::vector<double> x;
    for (int n = 0; n < static_cast<int>(0.25 * bench_sample_rate); ++n) {
        drop.body.step();
        x.push_back(elongation(drop.body) - rest);
    }
    return zero_crossing_hz(x, bench_sample_rate);
}

DropAccuracy measure_drop(Integrator integrator, int factor, double reference_hz, double seconds, int runs) {
    DropAccuracy d;
    d.hz = drop_frequency(integrator, factor, &d.sub_steps, &d.rayleigh_hz);
    d.cents = std::abs(1200.0 * std::log2(d.hz / reference_hz));
    double rest = 0.0;
    Drop drop = stretched_drop(integrator, factor, rest);
    d.ns_per_sample = time_per_sample(
                          [&](long n) {
                              for (long i = 0; i < n; ++i) drop.body.step();
                              bench_sink = bench_sink + drop.body.position(0).z;
                          },
                          seconds, runs)
                          .median_ns;
    return d;
}

}  // namespace ameoto::client
