// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the benchmark does to a body each sample, as templates so that the loop around step() is
// compiled for each body type (no virtual call per sample, as Faust's compute() has none either).
//
// Interface:
//   double sum = drive_impulses(body, node, samples, clock);   // 1 N for one sample every 0.1 s
//   PluckDrive pluck;                                          // triangleMesh.dsp's excitation
//   double sum = drive_pluck(body, pluck, excite, listen, samples, out);   // out may be null
//
// drive_pluck reproduces what the Faust program computes per sample (bench_mesh.hpp): the
// "Pluck Position" slider, +1 for pluck_period samples then -1, and so on, smoothed by si.smoo
// (p[n] = g s + (1 - g) p[n-1], g = 44.1 / fs), plucks t_m4_3 through mi.nlPluck(k = 0.5,
// scale = 0.03, z = 0.001): with d = p - x and dv = (p - p[n-1]) - (x - x[n-1]),
//   |d| < scale / 10: f = -(k - k/10) d + z dv
//   |d| < scale:      f = -sign(d) (scale / 10) k + (k / 10) d + z dv
//   otherwise:        f = 0
// on the mass (the position input takes -f and ignores it); the output is 30 x(t_m5_1). mi.lib
// computes the sample's forces from the positions at n and adds them at n + 1, as step() does, so
// out[n] = 30 x[n] is read before the step. The expressions keep Faust's order of operations.

#include <cmath>

namespace ameoto::client {

constexpr long impulse_period = 4800;   // samples between the impulse benchmark's forces (0.1 s)
constexpr long pluck_period = 24000;    // samples between slider flips (0.5 s at 48 kHz; 375 blocks of 64)

template <typename Body>
double drive_impulses(Body& body, int node, long samples, long& clock) {
    double sum = 0.0;
    for (long n = 0; n < samples; ++n, ++clock) {
        if (clock % impulse_period == 0) body.apply_force(node, 1.0);
        sum += body.step();
    }
    return sum;
}

struct PluckDrive {
    double gain = 44.1 / 48000.0;   // si.smoo at 48 kHz (Faust: 44.1 / fs)
    double pole = 1.0 - 44.1 / 48000.0;
    double p = 0.0, p_previous = 0.0, x_previous = 0.0;
    long clock = 0;

    double slider() const { return (clock / pluck_period) % 2 == 0 ? 1.0 : -1.0; }

    // The force on the plucked mass this sample, given its position x; advances the smoother.
    double force(double x) {
        p_previous = p;
        p = gain * slider() + pole * p;
        const double d = p - x;
        const double damping = 0.001 * (p + x_previous - (x + p_previous));
        x_previous = x;
        ++clock;
        const double a = std::fabs(d);
        if (a < 0.003) return damping - 0.45 * d;
        if (a < 0.03) return 0.5 * (0.0 - 0.003 * static_cast<double>((d > 0.0) - (d < 0.0))) + 0.05 * d + damping;
        return 0.0;
    }
};

template <typename Body>
double drive_pluck(Body& body, PluckDrive& pluck, int excite, int listen, long samples, double* out) {
    double sum = 0.0;
    for (long n = 0; n < samples; ++n) {
        body.apply_force(excite, pluck.force(body.position(excite)));
        const double y = 30.0 * body.position(listen);
        if (out) out[n] = y;
        sum += y;
        body.step();
    }
    return sum;
}

}  // namespace ameoto::client
