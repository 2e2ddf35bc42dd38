// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_accuracy_errors.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include <unsupported/Eigen/FFT>

namespace ameoto::client {

namespace {

constexpr double pi = 3.14159265358979323846;

std::vector<double> record_position(TransverseNetwork& net, const std::vector<double>& forces, int node, long samples) {
    net.reset();
    for (std::size_t i = 0; i < forces.size(); ++i)
        if (forces[i] != 0.0) net.apply_force(static_cast<int>(i), forces[i]);
    std::vector<double> x;
    x.reserve(static_cast<std::size_t>(samples));
    for (long n = 0; n < samples; ++n) {
        net.step();
        x.push_back(net.position(node));
    }
    return x;
}

// The part of a recorded mode where it dominates: up to its last sample above 1e-6 of its peak. Later,
// rounding's leakage into a slower-decaying mode (1e-12 and less of the amplitude; backward Euler damps
// high modes far faster than low ones) could outlast it and take over the zero crossings.
std::vector<double> dominant_part(std::vector<double> x) {
    double peak = 0.0;
    for (double v : x) peak = std::max(peak, std::abs(v));
    std::size_t end = x.size();
    while (end > 0 && std::abs(x[end - 1]) <= 1e-6 * peak) --end;
    x.resize(end);
    return x;
}

double peak_of(const std::vector<double>& x) {
    double peak = 0.0;
    for (double v : x) peak = std::max(peak, std::abs(v));
    return peak;
}

std::vector<double> record_response(TransverseNetwork& net, int node, long samples) {
    net.reset();
    net.apply_force(node, 1.0);
    std::vector<double> y;
    y.reserve(static_cast<std::size_t>(samples));
    for (long n = 0; n < samples; ++n) y.push_back(net.step());
    return y;
}

// Each reference mode's frequency in the method (NaN: a mode the method leaves out, modal truncation,
// whose answer is rounding noise only).
std::vector<double> mode_frequencies(TransverseNetwork& net, const AccuracyReference& reference, double fs) {
    std::vector<double> hz;
    for (std::size_t k = 0; k < reference.mode_hz.size(); ++k) {
        const std::vector<double> x = record_position(net, reference.shapes[k], reference.listen[k], frequency_samples);
        hz.push_back(peak_of(x) > 1e-6 * reference.mode_peak[k] ? zero_crossing_hz(dominant_part(x), fs)
                                                                : std::numeric_limits<double>::quiet_NaN());
    }
    return hz;
}

}  // namespace

TransverseNetwork build_network(const BenchMesh& mesh, const MethodSetting& setting) {
    TransverseNetwork net;
    for (std::size_t n = 0; n < mesh.nodes.size(); ++n) net.add_mass(mesh.node_mass, mesh.alpha * mesh.node_mass);
    for (const auto& l : mesh.links) net.add_link(l.a, l.b, l.k, mesh.beta * l.k);
    for (const auto& a : mesh.anchors) net.add_anchor(a.a, a.k, mesh.beta * a.k);
    NetworkOptions options = network_options_for(setting);
    options.guard.enabled = false;   // the measurement sees the scheme alone
    net.finalize(mesh.time_step, options);
    return net;
}

AccuracyReference make_reference(const BenchMesh& mesh, double max_hz) {
    TransverseNetwork exact = build_network(mesh, MethodSetting{Integrator::modal, 1, 0});
    const Modal& modal = exact.modal();
    const ModalDecomposition& all = modal.decomposition();
    const double w_max = all.net_force_weight.cwiseAbs().maxCoeff();
    AccuracyReference r;
    const double fs = 1.0 / mesh.time_step;
    for (Eigen::Index k = 0; k < all.omega.size() && all.omega[k] / (2.0 * pi) < max_hz; ++k) {
        if (std::abs(all.net_force_weight[k]) < 1e-6 * w_max) continue;   // inaudible (method_choice.cpp)
        std::vector<double> forces(mesh.nodes.size());
        Eigen::Index peak = 0;
        all.shapes.col(k).cwiseAbs().maxCoeff(&peak);
        for (std::size_t i = 0; i < forces.size(); ++i) forces[i] = mesh.node_mass * all.shapes(static_cast<Eigen::Index>(i), k);
        const std::vector<double> x = record_position(exact, forces, static_cast<int>(peak), frequency_samples);
        r.mode_hz.push_back(zero_crossing_hz(dominant_part(x), fs));
        r.mode_peak.push_back(peak_of(x));
        r.shapes.push_back(std::move(forces));
        r.listen.push_back(static_cast<int>(peak));
    }
    r.response = record_response(exact, mesh.excite_node, response_samples);
    return r;
}

MethodErrors measure_errors(const BenchMesh& mesh, const MethodSetting& setting, const AccuracyReference& reference) {
    TransverseNetwork net = build_network(mesh, setting);
    MethodErrors e;
    e.sub_steps = net.stability().sub_steps;
    e.modes_kept = net.integrator() == Integrator::modal ? net.modal().mode_count() : 0;
    const double fs = 1.0 / mesh.time_step;
    e.mode_hz = mode_frequencies(net, reference, fs);
    for (std::size_t k = 0; k < reference.mode_hz.size(); ++k) {
        const double hz = e.mode_hz[k];
        const double cents = std::isfinite(hz) ? std::abs(1200.0 * std::log2(hz / reference.mode_hz[k]))
                                               : std::numeric_limits<double>::infinity();
        e.cents = std::max(e.cents, cents);
    }
    e.decibels = log_spectral_distance_db(record_response(net, mesh.excite_node, response_samples), reference.response, fs);
    return e;
}

double zero_crossing_hz(const std::vector<double>& x, double sample_rate) {
    double first = -1.0, last = -1.0;
    int crossings = 0;
    for (std::size_t n = 1; n < x.size(); ++n) {
        const double a = x[n - 1], b = x[n];
        if ((a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0)) {
            if (b == 0.0) continue;   // touches zero: counted at the sign change that follows
            const double t = (static_cast<double>(n - 1) + a / (a - b)) / sample_rate;
            if (crossings == 0) first = t;
            last = t;
            ++crossings;
        }
    }
    if (crossings < 3) return std::numeric_limits<double>::quiet_NaN();
    return 0.5 * (crossings - 1) / (last - first);
}

double log_spectral_distance_db(const std::vector<double>& x, const std::vector<double>& reference, double sample_rate) {
    Eigen::FFT<double> fft;
    std::vector<std::complex<double>> a, b;
    fft.fwd(a, x);
    fft.fwd(b, reference);
    const std::size_t n = reference.size();
    const auto lo = static_cast<std::size_t>(std::ceil(20.0 * n / sample_rate));
    const auto hi = std::min(n / 2, static_cast<std::size_t>(20000.0 * n / sample_rate));
    double peak = 0.0;
    for (std::size_t i = lo; i <= hi; ++i) peak = std::max(peak, std::abs(b[i]));
    const double floor = peak * 1e-4;   // -80 dB
    double sum = 0.0;
    int bins = 0;
    for (std::size_t i = lo; i <= hi; ++i) {
        const double r = std::abs(b[i]);
        if (r < floor) continue;
        const double d = 20.0 * std::log10(std::max(std::abs(a[i]), floor) / r);
        sum += d * d;
        ++bins;
    }
    return bins > 0 ? std::sqrt(sum / bins) : 0.0;
}

double growth_factor(Integrator integrator, double omega_max_t) {
    constexpr int masses = 8;
    constexpr double m = 1e-3, k = 1000.0;
    TransverseNetwork net;
    for (int i = 0; i < masses; ++i) net.add_mass(m, 0.0);
    for (int i = 0; i + 1 < masses; ++i) net.add_link(i, i + 1, k, 0.0);
    net.add_anchor(0, k, 0.0);
    net.add_anchor(masses - 1, k, 0.0);
    const double omega_max = 2.0 * std::sqrt(k / m) * std::sin(masses * pi / (2.0 * (masses + 1)));
    NetworkOptions o;
    o.integrator = integrator;
    o.stability.policy = StabilityPolicy::none;
    o.guard.enabled = false;
    net.finalize(omega_max_t / omega_max, o);
    net.apply_force(0, 1.0);
    net.step();
    const double e1 = net.kinetic_plus_potential_energy();
    int n = 1;
    double e = e1;
    while (n < 2000) {
        net.step();
        ++n;
        e = net.kinetic_plus_potential_energy();
        if (!(e < 1e200 * e1)) break;
    }
    if (!std::isfinite(e)) return std::numeric_limits<double>::infinity();
    return std::pow(e / e1, 1.0 / (2.0 * (n - 1)));
}

double theoretical_growth(Integrator integrator, double x) {
    if (!conditionally_stable(integrator) || x <= 2.0) return 1.0;
    // Verlet's characteristic polynomial z^2 - (2 - x^2) z + 1: |z| = (x^2 - 2) / 2 + sqrt(((x^2 - 2) / 2)^2 - 1)
    // beyond x = 2 (symplectic Euler's is the same: its step matrix has trace 2 - x^2, determinant 1).
    const double h = (x * x - 2.0) / 2.0;
    return h + std::sqrt(h * h - 1.0);
}

}  // namespace ameoto::client
