// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace ameoto {

double StabilityReport::omega_max() const {
    return bound == StabilityBound::gershgorin ? omega_max_bound : omega_max_estimate;
}

double StabilityReport::margin() const {
    return explicit_margin(omega_max(), gamma_max_bound, time_step / sub_steps);
}

double explicit_margin(double omega, double gamma, double dt) {
    return (omega * omega * dt * dt + 2.0 * gamma * dt) / 4.0;
}

namespace {

// Gershgorin on a matrix M^-1 X whose row i is (diagonal_i + sum of i's links) / m_i on the diagonal and
// -link / m_i off it: the disc reaches (diagonal_i + 2 * sum of links) / m_i.
double gershgorin(const NetworkArrays& a, const std::vector<double>& diagonal, const std::vector<double>& per_link) {
    std::vector<double> sum(diagonal);
    for (std::size_t l = 0; l < a.link_count(); ++l) {
        sum[static_cast<std::size_t>(a.link_a[l])] += 2.0 * std::abs(per_link[l]);
        sum[static_cast<std::size_t>(a.link_b[l])] += 2.0 * std::abs(per_link[l]);
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < a.mass_count(); ++i) worst = std::max(worst, sum[i] * a.inverse_mass[i]);
    return worst;
}

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, fmt, a, b, c);
    return buffer;
}

}  // namespace

double gershgorin_omega_max(const NetworkArrays& arrays) {
    return std::sqrt(gershgorin(arrays, arrays.anchor_stiffness, arrays.link_stiffness));
}

double gershgorin_gamma_max(const NetworkArrays& arrays) {
    return gershgorin(arrays, arrays.ground_damping, arrays.link_damping);
}

double power_iteration_omega_max(const NetworkArrays& arrays, int max_iterations, double tolerance) {
    const std::size_t n = arrays.mass_count();
    if (n == 0) return 0.0;
    std::vector<double> s(n), v(n), u(n), w(n);
    for (std::size_t i = 0; i < n; ++i) s[i] = std::sqrt(arrays.inverse_mass[i]);
    // Deterministic start with every mode present: signs and sizes from a SplitMix64 sequence.
    std::uint64_t state = 0x9e3779b97f4a7c15ULL;
    double norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        v[i] = static_cast<double>(z >> 11) * 0x1.0p-53 * 2.0 - 1.0;
        norm += v[i] * v[i];
    }
    for (double& x : v) x /= std::sqrt(norm);
    double theta = 0.0, previous = -1.0;
    int settled = 0;
    for (int it = 0; it < max_iterations; ++it) {
        // w = M^-1/2 K M^-1/2 v; forces() gives -K u.
        for (std::size_t i = 0; i < n; ++i) u[i] = s[i] * v[i];
        arrays.forces(u.data(), nullptr, nullptr, w.data());
        theta = 0.0;
        norm = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            w[i] = -s[i] * w[i];
            theta += v[i] * w[i];
            norm += w[i] * w[i];
        }
        if (!(norm > 0.0)) return 0.0;   // K = 0
        norm = std::sqrt(norm);
        for (std::size_t i = 0; i < n; ++i) v[i] = w[i] / norm;
        settled = std::abs(theta - previous) <= tolerance * theta ? settled + 1 : 0;
        if (settled >= 3) break;
        previous = theta;
    }
    return std::sqrt(std::max(theta, 0.0));
}

namespace {

StabilityReport assess_for_stability(const NetworkArrays& arrays, double time_step_s, Integrator integrator,
                                     const StabilityOptions& options) {
    StabilityReport r;
    r.omega_max_bound = gershgorin_omega_max(arrays);
    r.omega_max_estimate = power_iteration_omega_max(arrays);
    r.gamma_max_bound = gershgorin_gamma_max(arrays);
    r.time_step = time_step_s;
    r.sub_steps = 1;
    r.requested = r.integrator = integrator;
    r.policy = options.policy;
    r.bound = options.bound;
    const char* name = integrator_name(integrator);
    const double omega = r.omega_max(), gamma = r.gamma_max_bound, t = time_step_s;
    const std::string numbers =
        format("omega_max T = %.3g (Gershgorin %.3g, power iteration %.3g)", omega * t, r.omega_max_bound * t,
               r.omega_max_estimate * t);
    if (!conditionally_stable(integrator)) {
        r.message = std::string(name) +
                    (integrator == Integrator::modal ? ": exact at any step; " : ": unconditionally stable; ") + numbers;
        return r;
    }
    const double margin = explicit_margin(omega, gamma, t);
    if (margin < options.safety) {
        r.message = std::string(name) + ": stable, " + numbers + format(", margin %.3g", margin);
        return r;
    }
    std::string why;
    if (omega * t >= 2.0) {
        why = format("omega_max T = %.3g exceeds 2 for the ", omega * t) + name + " scheme";
    } else {
        why = format("omega_max^2 T^2 + 2 gamma_max T = %.3g is within %.0f %% of the ", 4.0 * margin,
                     100.0 * (1.0 - options.safety)) + name + " scheme's limit 4";
    }
    why += format(" (Gershgorin %.3g, power iteration %.3g, gamma_max T = %.3g)", r.omega_max_bound * t,
                  r.omega_max_estimate * t, gamma * t);
    switch (options.policy) {
        case StabilityPolicy::none:
            r.message = why + "; running anyway (policy none): only the runtime guard protects it";
            return r;
        case StabilityPolicy::refuse:
            r.refused = true;
            r.message = why + "; use sub-steps or an implicit method";
            return r;
        case StabilityPolicy::switch_to_stable:
            r.integrator = Integrator::trapezoidal;
            r.message = why + "; switched to trapezoidal (unconditionally stable)";
            return r;
        case StabilityPolicy::sub_step: break;
    }
    // Fewest n with margin(T / n) < safety: T/n below the positive root of w^2 u^2 + 2 g u - 4 safety.
    const double s = options.safety;
    double u_max;
    if (omega > 0.0) u_max = (-2.0 * gamma + std::sqrt(4.0 * gamma * gamma + 16.0 * s * omega * omega)) / (2.0 * omega * omega);
    else u_max = 2.0 * s / gamma;
    const double needed = std::floor(t / u_max) + 1.0;
    if (!(needed <= static_cast<double>(options.max_sub_steps) + 1.0)) {
        r.refused = true;
        r.message = why + format("; needs %.0f sub-steps, more than the limit %.0f: use an implicit method", needed,
                                 static_cast<double>(options.max_sub_steps));
        return r;
    }
    int n = static_cast<int>(needed);
    while (explicit_margin(omega, gamma, t / n) >= s) ++n;
    while (n > 1 && explicit_margin(omega, gamma, t / (n - 1)) < s) --n;
    if (n > options.max_sub_steps) {
        r.refused = true;
        r.message = why + format("; needs %.0f sub-steps, more than the limit %.0f: use an implicit method",
                                 static_cast<double>(n), static_cast<double>(options.max_sub_steps));
        return r;
    }
    r.sub_steps = n;
    r.message = why + format("; running %.0f sub-steps (margin %.3g)", static_cast<double>(n), r.margin());
    return r;
}

}  // namespace

StabilityReport assess_stability(const NetworkArrays& arrays, double time_step_s, Integrator integrator,
                                 const StabilityOptions& options) {
    StabilityReport r = assess_for_stability(arrays, time_step_s, integrator, options);
    const int wanted = std::min(options.min_sub_steps, options.max_sub_steps);
    if (!r.refused && conditionally_stable(r.integrator) && wanted > r.sub_steps) {
        r.sub_steps = wanted;
        r.message += format("; %.0f sub-steps for accuracy (margin %.3g)", static_cast<double>(wanted), r.margin());
    }
    return r;
}

void RuntimeGuard::configure(const GuardOptions& options, double time_step_s) {
    options_ = options;
    forget_ = options.memory_s > 0.0 ? std::exp(-time_step_s / options.memory_s) : 1.0;
    amplitude_ = 0.0;
}

double RuntimeGuard::energy_limit() const {
    if (options_.energy_limit_J > 0.0) return options_.energy_limit_J;
    return options_.energy_factor * amplitude_ * amplitude_;
}

bool RuntimeGuard::exceeded(bool finite, double energy) const {
    if (!options_.enabled) return false;
    return !finite || !(energy <= energy_limit());
}

}  // namespace ameoto
