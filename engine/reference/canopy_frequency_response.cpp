// SPDX-License-Identifier: GPL-3.0-or-later
// The canopy in air in the frequency domain: see canopy_frequency_response.hpp.
#include "engine/reference/canopy_frequency_response.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/air_loading_helmholtz.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto::reference {

using cd = std::complex<double>;

AirMassAt compressible_air_mass(const Canopy& canopy, double air_density, double speed_of_sound, double step_hz) {
    if (!(step_hz > 0.0)) throw std::invalid_argument("compressible_air_mass: the step must be positive");
    auto cache = std::make_shared<std::map<long, std::vector<Eigen::MatrixXcd>>>();
    auto builder = std::make_shared<CanopyAirImpedanceBuilder>(canopy, air_density, speed_of_sound);
    auto at = [cache, builder, step_hz](long i) -> const std::vector<Eigen::MatrixXcd>& {
        auto it = cache->find(i);
        if (it == cache->end()) it = cache->emplace(i, builder->at(2.0 * constants::pi * step_hz * i).fourier).first;
        return it->second;
    };
    return [at, step_hz](double omega) {
        const double x = omega / (2.0 * constants::pi * step_hz);
        const long i = static_cast<long>(std::floor(x));
        const double t = x - i;
        const auto& a = at(i);
        if (t == 0.0) return a;
        const auto& b = at(i + 1);
        std::vector<Eigen::MatrixXcd> out(a.size());
        for (std::size_t m = 0; m < a.size(); ++m) out[m] = (1.0 - t) * a[m] + t * b[m];
        return out;
    };
}

AirMassAt incompressible_air_mass(const Canopy& canopy, double air_density) {
    const AddedMass a = canopy_added_mass(canopy, air_density);
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    std::vector<Eigen::MatrixXcd> fourier(static_cast<std::size_t>(panels), Eigen::MatrixXcd::Zero(nodes, nodes));
    // Block (0, d) of the circulant matrix is block d; mode m is sum_d e^(i theta_m d) block d.
    for (int m = 0; m < panels; ++m)
        for (int d = 0; d < panels; ++d)
            fourier[static_cast<std::size_t>(m)] +=
                std::polar(1.0, 2.0 * constants::pi * m * d / panels) * a.matrix.block(0, d * nodes, nodes, nodes).cast<cd>();
    return [fourier](double) { return fourier; };
}

namespace {

// The forces on the air per newton on (panel, node) at the Laplace variable s (s = i omega: a frequency),
// with the air's mass `ma` (its Fourier blocks): (K + s C + s^2 (M + M_a)) u = f, F = s^2 M_a u.
std::vector<cd> forces_at(const Canopy& canopy, int panel, int node, cd s, const std::vector<Eigen::MatrixXcd>& ma) {
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    if (panel < 0 || panel >= panels || node < 0 || node >= nodes) throw std::invalid_argument("canopy air forces: no such node");
    const auto& arrays = canopy.panel(0).network.arrays();
    const Eigen::MatrixXcd k = Eigen::MatrixXd(arrays.stiffness_matrix()).cast<cd>();
    const Eigen::MatrixXcd c = Eigen::MatrixXd(arrays.damping_matrix()).cast<cd>();
    // The force e_(panel, node) on the Fourier modes: y_m = (1 / N) e^(-i theta_m panel) e_node; each mode's
    // system is one panel's size.
    std::vector<Eigen::VectorXcd> f_m(static_cast<std::size_t>(panels));
    for (int m = 0; m < panels; ++m) {
        const double theta = 2.0 * constants::pi * m / panels;
        Eigen::MatrixXcd a = k + s * c + s * s * ma[static_cast<std::size_t>(m)];
        for (int i = 0; i < nodes; ++i) a(i, i) += s * s * arrays.mass(static_cast<std::size_t>(i));
        Eigen::VectorXcd y = Eigen::VectorXcd::Zero(nodes);
        y[node] = std::polar(1.0 / panels, -theta * panel);
        f_m[static_cast<std::size_t>(m)] = s * s * (ma[static_cast<std::size_t>(m)] * a.partialPivLu().solve(y));
    }
    std::vector<cd> out(static_cast<std::size_t>(panels * nodes));
    for (int p = 0; p < panels; ++p) {
        Eigen::VectorXcd force = Eigen::VectorXcd::Zero(nodes);
        for (int m = 0; m < panels; ++m) force += std::polar(1.0, 2.0 * constants::pi * m * p / panels) * f_m[static_cast<std::size_t>(m)];
        for (int i = 0; i < nodes; ++i) out[static_cast<std::size_t>(p * nodes + i)] = force[i];
    }
    return out;
}

// The forces' pressure at each listener (the double layer, s = i omega on the axis).
std::vector<cd> listeners_pressure(const Canopy& canopy, const std::vector<cd>& force, const std::vector<Vec3>& listeners, cd s,
                                   double speed_of_sound) {
    std::vector<cd> out(listeners.size());
    for (int p = 0; p < canopy.panel_count(); ++p)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            const Vec3 y = canopy.rest_position(p, i), n = canopy.normal(p, i);
            for (std::size_t l = 0; l < listeners.size(); ++l) {
                const Vec3 d = listeners[l] - y;
                const double r = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
                const double cos_theta = (d.x * n.x + d.y * n.y + d.z * n.z) / r;
                const cd g = std::exp(-s * (r / speed_of_sound)) * (1.0 / (r * r) + s / (speed_of_sound * r)) * (cos_theta / (4.0 * constants::pi));
                out[l] += g * force[static_cast<std::size_t>(p * canopy.nodes_per_panel() + i)];
            }
        }
    return out;
}

}  // namespace

std::vector<cd> canopy_air_forces(const Canopy& canopy, int panel, int node, double hz, const AirMassAt& air) {
    const double omega = 2.0 * constants::pi * hz;
    return forces_at(canopy, panel, node, cd(0.0, omega), air(omega));
}

std::complex<double> directional_force(const Canopy& canopy, const std::vector<cd>& forces, double k, double theta, double psi) {
    const double kx = k * std::sin(theta) * std::cos(psi), ky = k * std::sin(theta) * std::sin(psi);
    cd sum = 0.0;
    for (int p = 0; p < canopy.panel_count(); ++p)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            const Vec3 y = canopy.rest_position(p, i);
            sum += forces[static_cast<std::size_t>(p * canopy.nodes_per_panel() + i)] * std::polar(1.0, kx * y.x + ky * y.y);
        }
    return sum;
}

CanopyFrequencyResponse canopy_frequency_response(const Canopy& canopy, int panel, int node, const std::vector<Vec3>& listeners,
                                                  const std::vector<double>& hz, const AirMassAt& air, double speed_of_sound) {
    if (listeners.empty()) throw std::invalid_argument("canopy_frequency_response: no listener");
    CanopyFrequencyResponse out;
    out.hz = hz;
    out.pressure.assign(listeners.size(), std::vector<cd>(hz.size()));
    for (std::size_t f = 0; f < hz.size(); ++f) {
        const double omega = 2.0 * constants::pi * hz[f];
        const cd s(0.0, omega);
        const std::vector<cd> p = listeners_pressure(canopy, forces_at(canopy, panel, node, s, air(omega)), listeners, s, speed_of_sound);
        for (std::size_t l = 0; l < listeners.size(); ++l) out.pressure[l][f] = p[l];
    }
    return out;
}

std::vector<double> synthesize(const std::vector<cd>& laplace, double sigma, double period_s, double rate_hz, int samples) {
    // x(t) = e^(sigma t) (1 / T) sum_k X(sigma + i omega_k) e^(i omega_k t) over k = -K..K, X(conj) = conj(X):
    // the inverse of the Laplace transform sampled on the line Re s = sigma, periodic in T; the period's
    // wrapped tail is weighted by e^(-sigma T). The phasors e^(i omega_k t) are rotated, not recomputed.
    std::vector<double> out(static_cast<std::size_t>(samples));
    const double dw = 2.0 * constants::pi / period_s;
    for (int n = 0; n < samples; ++n) {
        const double t = n / rate_hz;
        const cd step = std::polar(1.0, dw * t);
        cd z = 1.0, sum = 0.5 * laplace[0];
        for (std::size_t k = 1; k < laplace.size(); ++k) {
            z *= step;
            sum += laplace[k] * z;
        }
        out[static_cast<std::size_t>(n)] = std::exp(sigma * t) * 2.0 * sum.real() / period_s;
    }
    return out;
}

std::vector<std::vector<double>> canopy_time_response(const Canopy& canopy, int panel, int node, const std::vector<Vec3>& listeners,
                                                      const AirMassAt& air, double speed_of_sound, const CanopyTimeResponseSetup& setup) {
    if (listeners.empty()) throw std::invalid_argument("canopy_time_response: no listener");
    if (!(setup.sigma > 0.0 && setup.period_s > setup.duration_s && setup.rate_hz > 2.0 * setup.max_hz && setup.max_hz > 0.0))
        throw std::invalid_argument("canopy_time_response: need sigma > 0, a period longer than the record and max_hz under half the rate");
    const auto bins = static_cast<std::size_t>(setup.max_hz * setup.period_s) + 1;
    std::vector<std::vector<cd>> spectrum(listeners.size(), std::vector<cd>(bins));
    for (std::size_t k = 0; k < bins; ++k) {
        const double omega = 2.0 * constants::pi * static_cast<double>(k) / setup.period_s;
        const cd s(setup.sigma, omega);
        // The air's mass at the frequency omega: on Re s = sigma it differs by O(sigma / omega) in k^2, where
        // the mass hardly depends on k at all (below 100 Hz it is the incompressible one).
        const std::vector<cd> p = listeners_pressure(canopy, forces_at(canopy, panel, node, s, air(omega)), listeners, s, speed_of_sound);
        const cd strike = raised_cosine_laplace(setup.force_n, setup.pulse_s, s);
        for (std::size_t l = 0; l < listeners.size(); ++l) spectrum[l][k] = p[l] * strike;
    }
    std::vector<std::vector<double>> out;
    const int samples = static_cast<int>(setup.duration_s * setup.rate_hz);
    for (const auto& x : spectrum) out.push_back(synthesize(x, setup.sigma, setup.period_s, setup.rate_hz, samples));
    return out;
}

std::complex<double> raised_cosine_laplace(double peak_n, double length_s, std::complex<double> s) {
    // (1 / 2) integral (1 - cos(a t)) e^(-s t) dt over one period of a = 2 pi / T:
    // (1 - e^(-s T)) a^2 / (2 s (s^2 + a^2)), T / 2 at s = 0 and -T / 4 at s = +/- i a.
    const double a = 2.0 * constants::pi / length_s;
    if (std::abs(s) < 1e-9 * a) return peak_n * length_s / 2.0;
    if (std::abs(s * s + a * a) < 1e-9 * a * a) return -peak_n * length_s / 4.0;
    return peak_n * (1.0 - std::exp(-s * length_s)) * (a * a) / (2.0 * s * (s * s + a * a));
}

std::complex<double> raised_cosine_spectrum(double peak_n, double length_s, double hz) {
    return raised_cosine_laplace(peak_n, length_s, cd(0.0, 2.0 * constants::pi * hz));
}

}  // namespace ameoto::reference
